// Melanin concentrations of real hair colours, turned into absorption by sigma_a_from_melanin
// (host/fiber/material.cpp).  Blond, brown and black are the concentrations the Chiang model is
// usually given for them (docs/CLI.md "Scenes", hair colour, has the sources); red is ours: a blond base plus
// enough pheomelanin that red clearly dominates (sigma_a ~ 0.41, 0.81, 1.99 per unit radius).
#include "scene/hair_presets.h"

namespace ht {

const std::vector<HairPreset>& hair_presets() {
    static const std::vector<HairPreset> table = {
        {"blond", 0.3f, 0.0f, "golden blond (pbrt: eumelanin 0.3)"},
        {"brown", 1.3f, 0.0f, "brown (pbrt: eumelanin 1.3)"},
        {"black", 8.0f, 0.0f, "black (pbrt: eumelanin 8)"},
        {"red", 0.3f, 1.5f, "red (eumelanin 0.3 + pheomelanin 1.5)"},
    };
    return table;
}

const HairPreset* find_hair_preset(const std::string& name) {
    for (const HairPreset& p : hair_presets())
        if (name == p.name) return &p;
    return nullptr;
}

}  // namespace ht
