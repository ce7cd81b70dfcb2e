/* Lobe features (host/render/features.cpp): a scene whose every Marschner-family / Chiang material
 * absorbs so strongly that a lobe's energy stays under the stated threshold for every angle and
 * offset gets that lobe compiled out of the render program (-DHT_FEATURE_LOBE_TT=0 / _TRT=0).
 * Evaluation, the pdf and the lobe-selection probabilities drop it together, so sampling stays
 * consistent with evaluation (the dropped lobe has pdf 0, the others are renormalised).
 * Undefined = in: the host tests and `hairtrace fiber` always see the complete models.
 * Chiang: HT_FEATURE_LOBE_TRT gates TRT and the TRRT+ residual (whose bound is below TRT's). */
#ifndef HT_FIBER_LOBES_H
#define HT_FIBER_LOBES_H

#include "../features.h"

/* Lobe p (0 R, 1 TT, 2 TRT, 3 chiang's residual) compiled in?  A constant expression: the loops
 * over p unroll and the dropped lobes' work disappears. */
#define HT_LOBE_ON(p) ((p) == 0 ? 1 : ((p) == 1 ? HT_FEATURE_LOBE_TT : HT_FEATURE_LOBE_TRT))
#define HT_LOBES_ON (1 + HT_FEATURE_LOBE_TT + 2 * HT_FEATURE_LOBE_TRT) /* of chiang's four */

#endif
