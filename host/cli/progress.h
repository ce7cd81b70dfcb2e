// Progress of a render on stderr.  On a terminal one line is rewritten in place (\r); in a log
// file, where \r would join every update into one endless line, a whole line is written for the
// first update, then at most every few seconds, and for the last.
#pragma once

namespace ht {

class Progress {
public:
    // Silent when !enabled (--quiet, MPI ranks other than 0).  Terminal or not: isatty(stderr).
    explicit Progress(bool enabled, double seconds_between_lines = 5.0);
    void update(int done, int total, double elapsed_seconds);
    // Ends the line rewritten in place, so that what follows starts on a line of its own.
    void finish();

private:
    bool enabled_, terminal_;
    double seconds_between_lines_;
    double last_line_at_ = -1;
    int last_done_ = -1;
    bool line_open_ = false;
};

}  // namespace ht
