#pragma once
// What a bop-haptic run says of its 1 kHz loop, checked without a wall-clock rate, which a busy
// 2-core machine may miss (the rate is scripts/bench/haptic.sh's to report):
// - every deadline up to the last tick's was a tick or is counted as missed;
// - the ticks' own work never blocked for `blockBoundMs` or more in one tick (a loop that waited
//   on the server would block for a round trip; blocks in which the machine paged code in from
//   disk are the machine's, counted apart by the client). The deadlines it missed were then the
//   machine's: late wake-ups and time on the run queue (a virtual machine's host can wake a
//   sleeping thread milliseconds late, which no figure inside the machine shows), printed.
// `printed` is the client's output, `trace` its haptic-trace.csv.
#include <string>

namespace bop::test {

void checkHapticLoop(const std::string& printed, const std::string& trace, double blockBoundMs);

}  // namespace bop::test
