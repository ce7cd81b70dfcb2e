#include "cli/progress.h"

#include <cstdio>
#include <unistd.h>

namespace ht {

Progress::Progress(bool enabled, double seconds_between_lines)
    : enabled_(enabled), terminal_(::isatty(::fileno(stderr)) == 1), seconds_between_lines_(seconds_between_lines) {}

void Progress::update(int done, int total, double elapsed) {
    if (!enabled_ || done == last_done_) return;
    last_done_ = done;
    const double eta = done > 0 ? elapsed / done * (total - done) : 0;
    if (terminal_) {
        std::fprintf(stderr, "\rrendering: %d/%d spp  %.1f s elapsed  ETA %.1f s   ", done, total, elapsed, eta);
        line_open_ = true;
    } else {
        const bool first = last_line_at_ < 0, last = done >= total;
        if (!first && !last && elapsed - last_line_at_ < seconds_between_lines_) return;
        last_line_at_ = elapsed;
        std::fprintf(stderr, "rendering: %d/%d spp  %.1f s elapsed  ETA %.1f s\n", done, total, elapsed, eta);
    }
    std::fflush(stderr);
}

void Progress::finish() {
    if (line_open_) std::fputc('\n', stderr);
    line_open_ = false;
}

}  // namespace ht
