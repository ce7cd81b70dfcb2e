#include "trace_bench_scene.h"

#include <cmath>
#include <random>

namespace ht_bench {

const TraceScene& trace_scene() {
    static const TraceScene scene = [] {
        TraceScene s;
        std::mt19937 rng(42);
        std::uniform_real_distribution<double> u(-1, 1);
        std::normal_distribution<double> g;
        ht::Strands st;
        st.first_point.push_back(0);
        for (int i = 0; i < 2000; ++i) {
            double p[3] = {u(rng), u(rng), u(rng)}, d[3] = {u(rng), u(rng), u(rng)};
            for (int j = 0; j <= 50; ++j) {
                st.points.push_back({(float)p[0], (float)p[1], (float)p[2]});
                st.radius.push_back(0.01f);
                const double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
                for (int k = 0; k < 3; ++k) p[k] += d[k] / n * 0.05;
                for (int k = 0; k < 3; ++k) d[k] = d[k] / n + 0.3 * u(rng);
            }
            st.first_point.push_back((uint32_t)st.points.size());
            st.material.push_back(0);
        }
        s.geo = ht::build_geometry(st);
        for (int i = 0; i < 65536; ++i) {
            const double x = (i % 256) / 128.0 - 1, y = (i / 256) / 128.0 - 1;
            const double l = std::sqrt(x * x + y * y + 36);
            s.primary.push_back(HtRay{0.0f, 0.0f, 6.0f, 0.0f, (float)(x * 1.2 / l),
                                      (float)(y * 1.2 / l), (float)(-6 / l), INFINITY});
            double d[3] = {g(rng), g(rng), g(rng)};
            const double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            s.incoherent.push_back(HtRay{(float)u(rng), (float)u(rng), (float)u(rng), 0.0f,
                                         (float)(d[0] / n), (float)(d[1] / n), (float)(d[2] / n),
                                         INFINITY});
        }
        return s;
    }();
    return scene;
}

}  // namespace ht_bench
