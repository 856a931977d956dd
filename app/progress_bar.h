#pragma once
// The command-line tool's view of a long job's Progress (model/progress.h), on stderr.
//
// On a terminal: one line redrawn in place ('\r') at most 10 times a second, once the stage has
// run for more than 1 s (quicker stages print nothing):
//   [producing tiles] [##########..........] 2048/4096 tiles 50% 310/s ETA 0:07
// with a count and a rate, no bar or ETA, when the total is unknown; when a stage that ran more
// than 1 s ends, the bar gives way to the plain line below.
// Elsewhere (a log, a pipe): plain lines only, one every 10 s while a stage runs and one when it
// ends:
//   [fitting splines] 1234 curves in 2.3 s (536/s)
//
// Order of calls: as Progress says; begin() and end() from one thread, advance() from any number
// of threads in between. Only one thread draws at a time, and a thread that finds another drawing
// goes on with its work.

#include <atomic>
#include <cstddef>
#include <functional>
#include <iosfwd>
#include <mutex>
#include <string>

#include "model/progress.h"

namespace lacet::app {

class TerminalProgress : public Progress {
public:
    // Seconds on a monotonic clock.
    using Seconds = std::function<double()>;

    // On stderr, as a bar when stderr is a terminal, timed by std::chrono::steady_clock.
    TerminalProgress();
    // On `out` (which must outlive this), as a bar when `terminal`, timed by `now` (for tests).
    TerminalProgress(std::ostream& out, bool terminal, Seconds now);
    // Ends the current stage, if any.
    ~TerminalProgress() override;
    TerminalProgress(const TerminalProgress&) = delete;
    TerminalProgress& operator=(const TerminalProgress&) = delete;

    void begin(const std::string& stage, std::size_t total, const std::string& unit) override;
    void advance(std::size_t units = 1) override;
    void end() override;

    // The stage runs this long before a terminal shows it (seconds).
    static constexpr double kTerminalDelay = 1.0;
    // Least time between two redraws of the bar (seconds).
    static constexpr double kTerminalInterval = 0.1;
    // Least time between two lines in plain mode while a stage runs (seconds).
    static constexpr double kPlainInterval = 10.0;

private:
    // The line of the running stage (`final`: the one that says it ended); `now` in seconds.
    std::string line(double now, bool final) const;
    // Writes the running stage's line, under drawing_.
    void draw(double now);

    std::ostream& out_;
    const bool terminal_;
    const Seconds now_;

    // The current stage: written by begin() only, while no advance() runs.
    bool open_ = false;
    std::string stage_, unit_;
    std::size_t total_ = 0;
    double start_ = 0.0;

    std::atomic<std::size_t> done_{0};
    std::atomic<double> nextDraw_{0.0};  // no line before this time (seconds)
    std::mutex drawing_;
    std::size_t barWidth_ = 0;  // characters of the bar now on the terminal's line, 0: none
};

}  // namespace lacet::app
