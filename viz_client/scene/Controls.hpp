#pragma once
// The values behind the panel's sliders and the commands they become, GL-free: interspecies
// weights (LJ, co-normal, co-planar), the probe's k0 and k1, and per-species damping, starting
// from the server's values (SceneInfo tunables). The panel edits `now`; commands() turns every
// value that differs from what was last sent into a SetParameter command (names and units in
// protocol/schemas/command.fbs) and takes it as sent. Also the one-off commands of the panel:
// seed, birth, run control, record.
#include "codec/Messages.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace bop::viz {

class Controls {
public:
    Controls() = default;
    // From the server's handshake; a server that sent no tunables gives weights 1, damping 0
    // and k0 = k1 = 1, and nothing is sent until a slider moves.
    explicit Controls(const protocol::SceneInfo& scene);

    int species() const { return n_; }
    protocol::Tunables now;  // what the sliders show; matrices n x n, row = receiving species

    // SetParameter commands for every value changed since the last call (or the handshake).
    std::vector<protocol::Command> commands();

private:
    int n_ = 0;
    protocol::Tunables sent_;
};

// The panel's one-off commands (request ids are set by whoever sends them).
protocol::Command seedCommand(int species, const Eigen::Vector3d& position);  // position: length
// A blade of `radius` swept from `from` to `to` (length).
protocol::Command cutCommand(const Eigen::Vector3d& from, const Eigen::Vector3d& to, double radius);
protocol::Command birthCommand(int species, bool on);
protocol::Command runCommand(protocol::RunAction action, std::uint32_t steps = 1);
protocol::Command recordCommand(bool start, const std::string& fileName = {});  // empty: the server's default

}  // namespace bop::viz
