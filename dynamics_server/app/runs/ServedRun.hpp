#pragma once
// bop-server with its network front (docs/protocol.md): the run (core/Run.hpp) at any rank
// count, rank 0 serving viewers and haptic clients; the loop itself is ServedLoop.hpp.
#include "app/runs/ExitCodes.hpp"
#include "app/scene/RunStart.hpp"
#include "core/Run.hpp"
#include "recording/SessionReader.hpp"
#include "server/ServerFront.hpp"

#include <optional>
#include <set>
#include <string>

namespace bop::app {

struct ServeOptions {
    protocol::FrontOptions front;
    long long steps = 0;         // stop after this many steps; 0 = until SIGINT or SIGTERM
    bool waitForClient = false;  // hold the first step until a client said Hello
    std::string outDir;          // final.xyz goes here
    // Replay a recorded session's inputs instead of listening to clients' (bop-replay check):
    // its commands and probes at the steps they were applied, frames at the steps it has
    // frames of, and stop after the last of them.
    std::optional<protocol::RecordedSession> replay;
    long long checkpointEvery = 0;  // steps between checkpoints; one is always written when the run stops
};

// Collective: every process calls it, with the exchanges of its kind (core::oneProcess(),
// parallel::rankExchanges()). Returns the exit code. However it stops, it writes
// <out>/checkpoint.xyz: the state at the end, or after kExitUnsound the last sound state (and
// no final.xyz).
int runServed(const Scene& scene, RunStart start, const ServeOptions& options, core::ExchangeMaker exchanges);

// The handshake's description of a scene (species with colours, box, map grid when `map`, a
// header or whole map, is given, r0, dt): `model` the run's (RunStart::model).
protocol::SceneInfo sceneInfoOf(const Scene& scene, const core::Model& model, const GradientMap* map);

}  // namespace bop::app
