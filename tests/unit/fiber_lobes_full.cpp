// The complete fibre models (default flags: every lobe in), for the lobes-off TUs to compare with.
#include "kernels/fiber/bcsdf.h"

namespace lobes_full {
void eval_lobes(const HtMaterial* m, real3 wo, real3 wi, double h, real3* lobes) {
    real3 v;
    real pdf;
    ht_bcsdf_eval_lobes(m, wo, wi, h, lobes, &v, &pdf);
}
}  // namespace lobes_full
