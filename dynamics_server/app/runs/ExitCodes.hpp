#pragma once
// bop-server's exit codes besides 0 and 2 (bad input: a file, key or option named): runs that
// stopped on their own, on every rank alike.
namespace bop::app {

inline constexpr int kExitUnsound = 3;         // the physics made an unsound state (core/SoundState.hpp)
inline constexpr int kExitStoppedByError = 4;  // an error stopped the run (RunLifecycle.hpp); its state is saved

}  // namespace bop::app
