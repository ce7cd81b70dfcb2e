/* Layouts of the fibre query kernel (fiber_query.cl), shared with host/fiber/fiber_cli.cpp. */
#ifndef HT_FIBER_QUERY_H
#define HT_FIBER_QUERY_H

#include "../types.h"

typedef struct {
    float wo[4];           /* xyz */
    float wi[4];           /* xyz (eval) */
    float h, u0, u1, u2;
    float u3;
    float lobe_weight;     /* sample: nonzero asks for the drawn lobe's weight (mixture 0 in bcsdf.h) */
    float pad1, pad2;
} HtFiberQuery;            /* 64 bytes */

typedef struct {
    float value[4];        /* eval: value; sample: weight */
    float lobes[4][4];     /* eval: R, TT, TRT, residual */
    float wi[4];           /* sample: sampled direction */
    float pdf, ok, pad0, pad1;
} HtFiberResult;           /* 112 bytes */

#endif
