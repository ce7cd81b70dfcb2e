// Hair colours of real hair as melanin concentrations (host/scene/hair_presets.cpp holds the
// table and where its numbers come from).
#pragma once

#include <string>
#include <vector>

namespace ht {

struct HairPreset {
    const char* name;
    float eumelanin, pheomelanin;  // concentrations, converted by sigma_a_from_melanin
    const char* description;
};

// The table, in the order `--hair-preset` lists it.
const std::vector<HairPreset>& hair_presets();

// The preset called `name`, or nullptr.
const HairPreset* find_hair_preset(const std::string& name);

}  // namespace ht
