#include "IgtlBridge.hpp"

#include "bop/common/Error.hpp"
#include "bop/common/GradientMap.hpp"
#include "bop/common/GradientMapFile.hpp"
#include "client/ClientSession.hpp"

#include <mutex>
#include <optional>
#include <thread>

namespace bop::igtl {
namespace {

using Clock = std::chrono::steady_clock;

// The label image of one map: each voxel's bag, its voxel centres in model mm.
LabelImage labelsOf(const GradientMap& m) {
    LabelImage img;
    const Dims& d = m.dims();
    img.dims = {d.nx, d.ny, d.nz};
    img.labels.resize(m.occ.size());
    for (std::size_t v = 0; v < m.occ.size(); ++v) img.labels[v] = std::uint8_t(bagOfSpecies(m.occ[v]));
    img.ijkToRas.setIdentity();
    img.ijkToRas.topLeftCorner<3, 3>() *= m.grid.voxelMm;
    img.ijkToRas.block<3, 1>(0, 3) = m.grid.centreMm(m.origin.x(), m.origin.y(), m.origin.z());
    return img;
}

// The particles of a frame in model mm: surface (with normals) and volume.
void pointSets(const protocol::SceneInfo& scene, const protocol::StateFrame& f, PointSet& surface, PointSet& volume) {
    surface = {}, volume = {};
    const std::size_t n = f.count();
    const bool normals = f.normals.size() == 3 * n;
    for (std::size_t k = 0; k < n; ++k) {
        const int s = f.species[k];
        const Eigen::Vector3d sim(f.positions[3 * k], f.positions[3 * k + 1], f.positions[3 * k + 2]);
        const Eigen::Vector3f x = toMm(scene, sim).cast<float>();
        if (isSurfaceSpecies(s)) {
            surface.points.push_back(x);
            if (normals) surface.normals.emplace_back(f.normals[3 * k], f.normals[3 * k + 1], f.normals[3 * k + 2]);
            surface.species.push_back(float(s));
        } else {
            volume.points.push_back(x);
            volume.species.push_back(float(s));
        }
    }
}

Eigen::Matrix4d translation(const Eigen::Vector3d& t) {
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.block<3, 1>(0, 3) = t;
    return m;
}

}  // namespace

Eigen::Vector3d toMm(const protocol::SceneInfo& scene, const Eigen::Vector3d& sim) {
    return scene.gridOriginMm + scene.unitSystem.lengthMm * sim;
}

Eigen::Vector3d fromMm(const protocol::SceneInfo& scene, const Eigen::Vector3d& mm) {
    return (mm - scene.gridOriginMm) / scene.unitSystem.lengthMm;
}

BridgeStats runBridge(const BridgeOptions& o, const std::atomic<bool>& stop,
                      const std::function<void(const std::string&)>& log, const std::function<void(int)>& listening) {
    protocol::ClientOptions co;
    co.clientName = "bop-igtl";
    co.frameRateHz = float(o.rateHz);
    protocol::ClientSession session(co);
    const protocol::SceneInfo scene = session.connect(o.endpoint, o.timeout);
    if (!scene.unitSystem.lengthKnown() || scene.mapBytes == 0)
        throw Error("bop-igtl", "the run at " + o.endpoint +
                                    " has no voxel grid in mm (bulk material): nothing to place in a scan");
    const std::vector<std::uint8_t> bytes = session.downloadMap(o.maxMapBytes, o.timeout);
    const std::optional<std::vector<GradientMap>> maps = readGradientMaps(bytes, scene.mapKey, "the run's map");
    if (!maps || maps->empty()) throw Error("bop-igtl", "the run's gradient map is not its scene's (key mismatch)");
    std::vector<Bytes> greeting;
    for (std::size_t k = 0; k < maps->size(); ++k)
        greeting.push_back(
            labelImage(k == 0 ? "BoP labels" : "BoP labels " + std::to_string(k + 1), labelsOf((*maps)[k])));

    std::mutex m;
    std::optional<Eigen::Vector3d> tip;  // mm, the newest tool transform's translation
    Clock::time_point tipAt{};
    BridgeStats stats;
    Server server(
        o.igtl, {"TRANSFORM"},
        [&](const Header& h, std::span<const std::uint8_t> content) {
            if (h.device != o.tool) return;
            Eigen::Matrix4d t;
            std::string error;
            if (!readTransform(content, t, error)) {
                log("TRANSFORM '" + h.device + "' refused: " + error);
                return;
            }
            std::lock_guard lock(m);
            tip = t.block<3, 1>(0, 3);
            tipAt = Clock::now();
        },
        log);
    server.setGreeting(std::move(greeting));
    log("OpenIGTLink on " + o.igtl.bind + ":" + std::to_string(server.port()) + "; the bag at " +
        std::to_string(o.rateHz) + " Hz from " + o.endpoint + "; TRANSFORM '" + o.tool + "' moves the probe");
    if (listening) listening(server.port());

    session.startReceiver();
    const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / o.rateHz));
    const Clock::time_point start = Clock::now();
    Clock::time_point next = start;
    std::uint64_t seenFrames = 0, probeSeq = 0;
    std::optional<protocol::Feedback> feedback;
    bool probing = false;
    PointSet surface, volume;
    while (!stop && (o.seconds <= 0 || Clock::now() - start < std::chrono::duration<double>(o.seconds))) {
        next += period;
        std::this_thread::sleep_until(next);
        if (Clock::now() > next + 4 * period) next = Clock::now();  // fell behind: do not catch up
        while (auto fb = session.pollFeedback()) feedback = fb;     // also keeps the session alive
        std::optional<Eigen::Vector3d> tool;
        {
            std::lock_guard lock(m);
            if (tip && Clock::now() - tipAt < std::chrono::seconds(1)) tool = tip;
        }
        if (tool || probing) {  // the tool's newest tip, or letting go once it has stopped
            protocol::Probe p;
            p.seq = ++probeSeq;
            p.clientTimeNs =
                std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
            p.active = bool(tool);
            p.k0 = o.k0, p.k1 = o.k1;
            p.position = tool ? fromMm(scene, *tool) : Eigen::Vector3d::Zero();
            try {
                session.sendProbe(p);
                stats.probes += p.active;
            } catch (const std::exception& e) {
                log(std::string("probe not sent: ") + e.what());
            }
            probing = bool(tool);
        }
        const protocol::LatestFrame latest = session.latestFrame();
        if (!latest.frame || latest.count == seenFrames) continue;
        seenFrames = latest.count;
        const protocol::StateFrame& f = *latest.frame;
        pointSets(scene, f, surface, volume);
        server.publish("BoP surface", polyData("BoP surface", surface));
        server.publish("BoP volume", polyData("BoP volume", volume));
        const Eigen::Vector3d probeMm = toMm(scene, f.probePosition);
        server.publish("Probe", transform("Probe", translation(probeMm)));
        const Eigen::Vector3d forceN =
            f.probeActive ? Eigen::Vector3d(scene.unitSystem.toN(1.0) * f.probeForce) : Eigen::Vector3d::Zero();
        server.publish("ProbeForce",
                       line("ProbeForce", probeMm.cast<float>(), (probeMm + o.forceMmPerN * forceN).cast<float>()));
        ++stats.frames;
    }
    stats.igtl = server.stats();
    return stats;
}

}  // namespace bop::igtl
