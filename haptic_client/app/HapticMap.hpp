#pragma once
// The gradient map a haptic client renders as a force field: downloaded from the server at
// connect (MapRequest, protocol/client/ClientSession.hpp), read as a .bopgm file.
#include "client/ClientSession.hpp"
#include "control/FieldForce.hpp"

#include <optional>

namespace bop::haptic {

// The field of the server's map (its first frame), or nothing when the server offers none.
// bop::Error when the download fails or the file does not read as the announced map.
std::optional<FieldForce> downloadField(protocol::ClientSession& session, const protocol::SceneInfo& scene,
                                        double stiffness, double maxMb);

// Where a poke from above meets the bag: the field's top, or without a map the top centre of
// the box.
Eigen::Vector3d topOfBag(const std::optional<FieldForce>& field, const protocol::SceneInfo& scene);

}  // namespace bop::haptic
