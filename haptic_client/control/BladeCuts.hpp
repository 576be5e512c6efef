#pragma once
// Cutting from the haptic loop (docs/haptics.md "Cutting"): the hand's path, while the cut is on,
// becomes strokes of a blade, each sent as a Cut command without waiting; the client's own copy
// of the gradient map takes the same edit on a thread of its own (bop/common/GradientMapEdit.hpp),
// so that its field follows the server's map and the loop never waits for either. The edits other
// clients and the server make reach the copy the same way (MapFollow.hpp).
#include "bop/common/SurfaceFilters.hpp"
#include "control/FieldForce.hpp"

#include <Eigen/Core>

#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace bop::haptic {

struct Stroke {
    Eigen::Vector3d from = Eigen::Vector3d::Zero(), to = Eigen::Vector3d::Zero();  // length
    double radius = 0;                                                             // length
};

// The path of the blade: a stroke from where the last one ended once the blade has gone a
// stroke's length (`radius` by default) and `minIntervalS` has passed; a press starts a path.
class BladePath {
public:
    BladePath(double radius, double minIntervalS = 0.02) : radius_(radius), minIntervalS_(minIntervalS) {}
    // One tick: whether the cut is on, the blade at x (length), at tS (s).
    std::optional<Stroke> tick(double tS, bool cutting, const Eigen::Vector3d& x);

private:
    double radius_, minIntervalS_;
    std::optional<Eigen::Vector3d> last_;  // where the path's last stroke ended (none: not cutting)
    double lastS_ = -1e300;
};

// One edit of the map's copy: a stroke of the blade, or (stroke.radius 0) voxels that leave their
// bags (whole-map linear indices, increasing: a yield of the server's, protocol MapEdit).
struct CopyEdit {
    Stroke stroke;
    std::vector<std::uint64_t> voxels;
};

// Applies edits to a field's map on its own thread, in the order given; push() never waits for
// an edit (only for the queue's lock, held for a push or a pop). An edit the map refuses (one
// that would take every bag, voxels beyond the grid) leaves the map as it was and is counted.
class FieldCutter {
public:
    FieldCutter(FieldForce& field, SurfaceGeometryParams geometry);
    ~FieldCutter();  // finishes the edits queued, then joins
    FieldCutter(const FieldCutter&) = delete;
    FieldCutter& operator=(const FieldCutter&) = delete;

    void push(const Stroke& s);
    void push(CopyEdit e);
    void drain();                 // waits until every edit pushed so far is in the map (tests, the end of a run)
    std::size_t applied() const;  // edits done, refused ones included
    std::size_t refused() const;
    std::string lastRefusal() const;
    double slowestMs() const;  // the longest edit so far, ms

private:
    void work();
    void apply(const CopyEdit& e);  // never throws: a refusal is counted
    FieldForce& field_;
    SurfaceGeometryParams geometry_;
    mutable std::mutex m_;
    std::condition_variable wake_, done_;
    std::deque<CopyEdit> queue_;
    bool stop_ = false, busy_ = false;
    std::size_t applied_ = 0, refused_ = 0;
    std::string lastRefusal_;
    double slowestMs_ = 0;
    std::thread worker_;
};

}  // namespace bop::haptic
