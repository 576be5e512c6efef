#include "app/HapticMap.hpp"

#include "bop/common/Error.hpp"
#include "bop/common/GradientMapFile.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>

namespace bop::haptic {

std::optional<FieldForce> downloadField(protocol::ClientSession& session, const protocol::SceneInfo& scene,
                                        double stiffness, double maxMb) {
    if (scene.mapBytes == 0) {
        std::printf("bop-haptic: the server offers no gradient map; no field force\n");
        return std::nullopt;
    }
    const auto t0 = std::chrono::steady_clock::now();
    int shown = -1;
    const std::vector<std::uint8_t> bytes = session.downloadMap(
        std::uint64_t(maxMb * 1e6), std::chrono::seconds(10), [&](std::uint64_t done, std::uint64_t total) {
            const int percent = int(100 * done / std::max<std::uint64_t>(total, 1));
            if (percent / 25 != shown / 25 || done == total) {
                shown = percent;
                std::printf("bop-haptic: gradient map %3d%% (%.2f of %.2f MB)\n", percent, double(done) / 1e6,
                            double(total) / 1e6);
                std::fflush(stdout);
            }
        });
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    // The file's reader checks magic, version, key and checksum, here on the bytes in memory.
    const std::optional<std::vector<GradientMap>> maps =
        readGradientMaps(bytes, scene.mapKey, "the downloaded gradient map");
    if (!maps || maps->empty())
        throw Error("bop-haptic", "the downloaded gradient map is not the scene's (key mismatch)");
    const Dims& d = maps->front().dims();
    std::printf("bop-haptic: gradient map %dx%dx%d voxels (%.2f MB in %.2f s)\n", d.nx, d.ny, d.nz,
                double(bytes.size()) / 1e6, s);
    return FieldForce(std::move(maps->front()), stiffness);
}

Eigen::Vector3d topOfBag(const std::optional<FieldForce>& field, const protocol::SceneInfo& scene) {
    if (field) return field->top();
    const Eigen::Vector3d c = 0.5 * (scene.boxLo + scene.boxHi);
    return {c.x(), c.y(), scene.boxHi.z()};
}

}  // namespace bop::haptic
