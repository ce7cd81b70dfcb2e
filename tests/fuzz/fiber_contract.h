// What every `hairtrace fiber eval|sample` JSON line must lead to, shared by the libFuzzer
// target and the ctest replay: either a refusal with a reason, or finite, non-negative values,
// pdfs and weights from the double-precision fibre models.  The first byte picks eval (even) or
// sample (odd); the rest is the line.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>

#include "fiber/query_json.h"
#include "kernels/fiber/bcsdf.h"

namespace ht_fuzz {

inline std::string judge_fiber_query(const uint8_t* data, size_t size) {
    if (size == 0) return "";
    const bool sample = (data[0] & 1) != 0;
    const std::string line(reinterpret_cast<const char*>(data) + 1, size - 1);
    ht::FiberJsonQuery q;
    try {
        q = ht::parse_fiber_query(line, sample);
    } catch (const std::exception& e) {
        return std::string("parse_fiber_query threw: ") + e.what();  // it must report, not throw
    }
    if (!q.valid) return q.error.empty() ? "refused without a reason" : "";
    auto bad = [](double x) { return !std::isfinite(x) || x < 0; };
    if (!sample) {
        real3 lobes[4], value;
        real pdf;
        ht_bcsdf_eval_lobes(&q.m, q.wo, q.wi, q.h, lobes, &value, &pdf);
        if (bad(value.x) || bad(value.y) || bad(value.z) || bad(pdf)) return "eval: non-finite or negative value/pdf";
        for (auto& l : lobes)
            if (bad(l.x) || bad(l.y) || bad(l.z)) return "eval: non-finite or negative lobe";
        return "";
    }
    real3 wi, weight;
    real pdf;
    if (!ht_bcsdf_sample(&q.m, q.wo, q.h, q.u[0], q.u[1], q.u[2], q.u[3], &wi, &weight, &pdf)) return "";
    if (bad(weight.x) || bad(weight.y) || bad(weight.z) || bad(pdf)) return "sample: non-finite or negative weight/pdf";
    if (!(std::fabs(length(wi) - 1.0) < 1e-6)) return "sample: direction is not a unit vector";
    return "";
}

}  // namespace ht_fuzz
