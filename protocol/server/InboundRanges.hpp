#pragma once
// The valid ranges that need the scene (docs/protocol.md, "Valid ranges"; the rest are the
// decoders', codec/Ranges.hpp): checked by the front on every probe, command and map request that
// passed its decoder, and by the server on replayed inputs. Each returns why the message is
// refused, or nothing when it may be applied.
#include "codec/Messages.hpp"

#include <Eigen/Geometry>

#include <optional>
#include <string>

namespace bop::protocol {

// Where a probe may be: the scene's box grown on every side by twice its largest side (a haptic
// workspace fitted to the box reaches beyond it along its shorter axes), length.
Eigen::AlignedBox3d probeReachBox(const SceneInfo& scene);

std::optional<std::string> refuseProbe(const Probe& p, const SceneInfo& scene);
// Species numbers within the scene's, seeds inside the box, weights between existing species.
// Parameter names the server does not know pass here and are answered Unsupported by it.
std::optional<std::string> refuseCommand(const Command& c, const SceneInfo& scene);
// A piece that begins beyond the end of the server's map file (SceneInfo::mapBytes).
std::optional<std::string> refuseMapRequest(const MapRequest& r, const SceneInfo& scene);

}  // namespace bop::protocol
