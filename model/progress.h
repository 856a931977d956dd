#pragma once
// Progress of a long job (an import, a render, a batch of tiles), reported by the code that does
// the work and shown by whoever runs it: a bar with a rate and an ETA on a terminal, plain lines
// in a log (app/progress_bar.h). The work code knows nothing of terminals; it calls, per stage,
//   begin("fitting splines", curves, "curves"); advance() ... from any thread; end();
// A null Progress* means nobody is watching.

#include <cstddef>
#include <string>

namespace lacet {

class Progress {
public:
    virtual ~Progress() = default;
    // Starts a stage of `total` units (0: unknown), named for the user; `unit` names one unit
    // ("features", "rows", "tiles"). Ends the previous stage if it was not ended.
    virtual void begin(const std::string& stage, std::size_t total, const std::string& unit) = 0;
    // `units` more units of the current stage are done. Safe to call from several threads.
    virtual void advance(std::size_t units = 1) = 0;
    // The current stage is finished.
    virtual void end() = 0;
};

// Calls of a Progress* that may be null.
inline void progressBegin(Progress* p, const std::string& stage, std::size_t total, const std::string& unit) {
    if (p) p->begin(stage, total, unit);
}
inline void progressAdvance(Progress* p, std::size_t units = 1) {
    if (p) p->advance(units);
}
inline void progressEnd(Progress* p) {
    if (p) p->end();
}

}  // namespace lacet
