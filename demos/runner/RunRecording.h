#pragma once
// The whole run, kept compactly so that any frame can be drawn again after the run (the story
// picture) and the run can be written as one animated file (glTF): per body, the shapes it
// had in its own coordinates and, per frame, its pose and which shape it had. A body that only
// moves keeps one shape for the whole run; a dent, a tear or a lost piece adds one; a soft
// body adds one per frame it deforms.
#include "demos/runner/NamedMesh.h"

#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace shatter::demo {

struct BodyKey {
    Eigen::Vector3d translation;
    Eigen::Quaterniond rotation; // unit; its sign keeps the shortest turn from the previous key
    int shape = -1;              // index into BodyTrack::shapes; -1 while the body is not there
};

struct BodyTrack {
    std::string name;   // unique in the run (a repeated name gets "#2", "#3", ...)
    bool ground = false;
    bool outlined = true;
    std::vector<geometry::VisualMesh> shapes; // body coordinates
    int firstFrame = 0;                       // frame of keys[0] (1-based)
    std::vector<BodyKey> keys;                // one per frame from firstFrame to the last frame it was seen

    int lastFrame() const { return firstFrame + int(keys.size()) - 1; }
    const BodyKey* at(int frame) const; // null when the body is not there
};

class RunRecording {
public:
    // Adds frame `frame` (1-based, one after the other). Bodies are matched to earlier frames
    // by name (the n-th body of a name to the n-th of earlier frames). A body's shape counts
    // as unchanged while its faces are the same and no vertex moved (in body coordinates) by
    // more than 1e-4 of its size: float poses alone move vertices by about 1e-7. `events` is the
    // number of Shatter events of the frame (kept for the outputs to show).
    void add(int frame, const std::vector<NamedMesh>& meshes, int events = 0);

    // Every body present at `frame`, in world coordinates, in the order first seen.
    std::vector<NamedMesh> meshesAt(int frame) const;

    const std::vector<BodyTrack>& tracks() const { return tracks_; }
    int frames() const { return frames_; }
    const std::vector<int>& eventsPerFrame() const { return events_; }

private:
    std::vector<BodyTrack> tracks_;
    std::vector<int> events_;
    int frames_ = 0;
};

} // namespace shatter::demo
