#pragma once
// The pyramid that goes with the scene file the editor edits (§7; pyramid/pyramid_reader.h,
// pyramid/pyramid_build.h): opened for each editing session, so that the appearance of the quads
// below its first vector level is read from it (EditSession::setPyramid); updated after each save
// to that scene file (`lacet pyramid update` on a copy of the saved document, or on the scene file
// for a session reading it lazily, in a background thread); reopened in the session when the update is done, with the edit count of the save (the
// quads edited since stay live). One update runs at a time: a save during it is queued, a later
// save replacing the queued one. A save to another file updates nothing (that file is another
// scene). The window (ui/editor_app.h) only shows what happens: the status line, its log, the
// Statistics panel.
//
// Order of calls: setFiles(); for each session, sessionStarted(session) then open(session);
// afterSave() after each save; poll() each frame (wait = true before the session or the program
// ends, so that no update outlives it).

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "editor/edit_session.h"
#include "io/document.h"

namespace lacet {

// The pyramid as the session reads it.
struct PyramidLevels {
    std::string path;
    int minLevel = 0, vectorLevel = 0, maxLevel = 0;  // levels minLevel..vectorLevel-1 are read from it
    std::string encoding;
};

// What opening the pyramid for a session did: opened (levels) or refused (error; the session goes
// on without it, every tile made live). Neither when there is no pyramid.
struct PyramidOpened {
    std::optional<PyramidLevels> levels;
    std::string error;
};

// An update after a save, as it ended.
struct PyramidUpdateResult {
    std::string path;
    std::uint64_t madeAt = 0;  // the session's edit count at the save it updated to
    std::size_t quads = 0, quadsChanged = 0, tilesMade = 0, tilesWritten = 0;
    double seconds = 0.0;
    bool rebuilt = false;
    bool updated = false;  // the update ran through (the figures above are its)
    std::string error;     // why it did not, or why the pyramid was not reopened after it; empty: both done
    bool ok() const { return error.empty(); }
};

class PyramidLink {
public:
    PyramidLink() = default;
    ~PyramidLink();  // waits for an update in flight
    PyramidLink(const PyramidLink&) = delete;
    PyramidLink& operator=(const PyramidLink&) = delete;

    // The pyramid file (empty: none) and the scene file whose saves update it. Call between
    // sessions (no update in flight: poll(session, true) first).
    void setFiles(std::string pyramid, std::string scene);
    // The scene file's default pyramid (pyramid/pyramid_build.h: defaultPyramidPath) when that
    // file exists, else none.
    void setDefaultFiles(const std::string& scene);
    const std::string& path() const { return pyramid_; }
    // The pyramid the session reads, as last opened (empty: none).
    const std::optional<PyramidLevels>& levels() const { return levels_; }

    // A new session: updates of the previous one no longer apply to it, and its last result is
    // forgotten.
    void sessionStarted();
    // Opens the pyramid for `session`. A pyramid that does not fit the scene is refused: the link
    // then has no file (path() empty) until setFiles().
    PyramidOpened open(EditSession& session);

    // After the session's document was saved to `target`: starts (or queues) the update when
    // `target` is the pyramid's scene file. Returns a message for the status line (empty: none).
    std::string afterSave(const EditSession& session, const std::string& target);

    // When the update in flight has ended (or, with `wait`, once it has): reopens the pyramid in
    // `session` (of the same session only), starts the queued update, and returns the result.
    std::optional<PyramidUpdateResult> poll(EditSession& session, bool wait);
    bool updating() const { return running_ != nullptr; }
    // The last update of this session that ended (none yet: empty).
    const std::optional<PyramidUpdateResult>& last() const { return last_; }

private:
    struct Running {
        std::thread thread;
        std::atomic<bool> done{false};
        std::shared_ptr<const SceneDocument> document;  // as saved; none: the scene file (a session reading it lazily)
        std::string checksum;                           // then: its stored checksum at the save
        std::uint64_t madeAt = 0, session = 0;
        PyramidUpdateResult result;
    };
    // An update to `saved`, or to the scene file as saved with `checksum` (saved null).
    void start(std::shared_ptr<const SceneDocument> saved, std::string checksum, std::uint64_t madeAt);

    std::string pyramid_, scene_;
    std::uint64_t session_ = 0;  // sessionStarted() count
    std::unique_ptr<Running> running_;
    bool queued_ = false;  // a save while an update ran:
    std::shared_ptr<const SceneDocument> queuedDocument_;
    std::string queuedChecksum_;
    std::uint64_t queuedAt_ = 0;
    std::optional<PyramidUpdateResult> last_;
    std::optional<PyramidLevels> levels_;
};

}  // namespace lacet
