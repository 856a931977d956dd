#include "editor/pyramid_link.h"

#include <filesystem>
#include <system_error>
#include <utility>

#include "pyramid/pyramid_build.h"
#include "pyramid/pyramid_reader.h"

namespace lacet {

PyramidLink::~PyramidLink() {
    if (running_ && running_->thread.joinable()) running_->thread.join();
}

void PyramidLink::setFiles(std::string pyramid, std::string scene) {
    pyramid_ = std::move(pyramid);
    scene_ = std::move(scene);
}

void PyramidLink::setDefaultFiles(const std::string& scene) {
    const std::string pyramid = defaultPyramidPath(scene);
    std::error_code e;
    setFiles(std::filesystem::exists(pyramid, e) ? pyramid : std::string(), scene);
}

void PyramidLink::sessionStarted() {
    ++session_;
    last_.reset();
}

PyramidOpened PyramidLink::open(EditSession& session) {
    PyramidOpened out;
    levels_.reset();
    if (pyramid_.empty()) return out;
    try {
        const SceneDocument& doc = session.document();
        auto reader = session.lazyForest()  // the top part's checksum is not the file's
                          ? std::make_shared<PyramidReader>(pyramid_, doc.scene.extent,
                                                            doc.georeference.valid ? doc.georeference.crsWkt : std::string(),
                                                            session.storedChecksum())
                          : std::make_shared<PyramidReader>(pyramid_, doc);
        session.setPyramid(reader);
        out.levels = levels_ = PyramidLevels{pyramid_, reader->minLevel(), reader->vectorLevel(), reader->maxLevel(), reader->encoding()};
    } catch (const std::exception& e) {
        out.error = e.what();
        pyramid_.clear();
    }
    return out;
}

std::string PyramidLink::afterSave(const EditSession& session, const std::string& target) {
    if (!session.pyramid()) return {};
    std::error_code e1, e2;
    const bool sameFile = !scene_.empty() &&
                          std::filesystem::weakly_canonical(target, e1) == std::filesystem::weakly_canonical(scene_, e2) && !e1 && !e2;
    if (!sameFile) return "Saved to another file than " + scene_ + ": its pyramid " + pyramid_ + " was not updated";
    const bool queued = running_ != nullptr;
    if (session.lazyForest())  // the file itself, saved in place (its document is a part of it)
        start(nullptr, session.storedChecksum(), session.editCount());
    else
        start(std::make_shared<const SceneDocument>(session.document()), {}, session.editCount());
    return "Updating the pyramid " + pyramid_ + (queued ? " after the update in flight..." : "...");
}

void PyramidLink::start(std::shared_ptr<const SceneDocument> saved, std::string checksum, std::uint64_t madeAt) {
    if (running_) {  // one update at a time: this one after it (a later save replaces it)
        queued_ = true;
        queuedDocument_ = std::move(saved);
        queuedChecksum_ = std::move(checksum);
        queuedAt_ = madeAt;
        return;
    }
    running_ = std::make_unique<Running>();
    Running* u = running_.get();
    u->document = std::move(saved);
    u->checksum = std::move(checksum);
    u->madeAt = madeAt;
    u->session = session_;
    u->result.path = pyramid_;
    u->result.madeAt = madeAt;
    u->thread = std::thread([u, scene = scene_] {
        try {
            const PyramidStats f = u->document ? updatePyramid(*u->document, u->result.path, nullptr) : updatePyramid(scene, u->result.path, nullptr);
            u->result.quads = f.quads, u->result.quadsChanged = f.quadsChanged, u->result.tilesMade = f.tilesMade;
            u->result.tilesWritten = f.tilesWritten, u->result.seconds = f.wallSeconds, u->result.rebuilt = f.rebuilt;
            u->result.updated = true;
        } catch (const std::exception& e) {
            u->result.error = e.what();
        }
        u->done = true;
    });
}

std::optional<PyramidUpdateResult> PyramidLink::poll(EditSession& session, bool wait) {
    if (!running_ || (!wait && !running_->done)) return std::nullopt;
    running_->thread.join();
    const std::unique_ptr<Running> u = std::move(running_);
    std::optional<PyramidUpdateResult> out;
    if (u->session == session_ && !pyramid_.empty()) {
        PyramidUpdateResult r = u->result;
        if (r.ok()) {
            try {
                // The saved document, which the pyramid now shows (edits made since stay live).
                const SceneDocument& doc = session.document();
                const std::string crs = doc.georeference.valid ? doc.georeference.crsWkt : std::string();
                std::shared_ptr<PyramidReader> reader;
                if (u->document) {
                    reader = std::make_shared<PyramidReader>(pyramid_, *u->document);
                } else {
                    // The file as the update read it: as saved then, or as a later save made it
                    // when that save came first (its update is queued).
                    reader = std::make_shared<PyramidReader>(pyramid_, doc.scene.extent, crs);
                    const std::string& made = reader->sceneChecksum();
                    if (made != u->checksum && made != session.storedChecksum())
                        reader = std::make_shared<PyramidReader>(pyramid_, doc.scene.extent, crs, u->checksum);  // refused, by name
                }
                session.setPyramid(reader, u->madeAt);
            } catch (const std::exception& e) {
                r.error = e.what();
            }
        }
        last_ = r;
        out = std::move(r);
    }
    if (queued_ && u->session == session_) {
        queued_ = false;
        start(std::move(queuedDocument_), std::move(queuedChecksum_), queuedAt_);
    }
    queued_ = false;
    queuedDocument_.reset();
    return out;
}

}  // namespace lacet
