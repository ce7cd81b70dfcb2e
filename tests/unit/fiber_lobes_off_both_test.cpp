// The fibre models compiled with HT_FEATURE_LOBE_TT=0, HT_FEATURE_LOBE_TRT=0 (fiber_lobes_test_body.h).
#define HT_FEATURE_LOBE_TT 0
#define HT_FEATURE_LOBE_TRT 0
#define HT_LOBES_SUITE FiberLobesOffBoth
#include "fiber_lobes_test_body.h"
