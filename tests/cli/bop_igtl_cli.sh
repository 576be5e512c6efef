#!/usr/bin/env bash
# bop-igtl against OpenIGTLink clients nobody in the project wrote in the code they run: the
# reference library's own example receiver (ReceiveClient, built from Debian's
# openigtlink-examples) and a client written from the protocol's specification
# (tests/igtl/igtl_spec_client.py). The placed torus is served at one rank; bop-igtl bridges it.
# The spec client gets the bag ("BoP surface" POLYDATA with normals and species) at the rate asked
# for, the label IMAGE once, and finds the surface particles on the image's surface; its
# TRANSFORM under the tool's name, 1 mm above the topmost particle, moves the probe there and the
# particles under it away (the tip's clearance grows by more than 1 mm); malformed input is
# refused with a reason (a header that breaks the rules closes that connection, a wrong CRC or an
# unknown type skips the message) while bop-igtl serves on; nine connections that never read cost
# a reading client its updates no more than it can spare.
# Usage: bop_igtl_cli.sh BOP_SERVER BOP_IGTL RECEIVE_CLIENT SOURCE_DIR
set -u
server=$1 igtl=$2 receive=$3 src=$4
source "$(dirname "$0")/cli-checks.sh"
py=/usr/bin/python3
client="$src/tests/igtl/igtl_spec_client.py"
scene="$src/config/scenes/torus.toml"

bounded 120 "$work/settle.log" "$server" "$scene" --no-listen --cache "$work/map.bopgm" -o "$work/settled"
check "the torus is placed and settled" "[ -s '$work/settled/final.xyz' ]"
"$server" "$scene" --restart "$work/settled/final.xyz" --cache "$work/map.bopgm" --port 0 --steps 1000000000 \
  -o "$work/served" >"$work/server.log" 2>&1 &
spid=$!
endpoint=$(first_match "$work/server.log" 's/^listening on \(tcp:[^ ]*\).*/\1/p')
check "the server listens" "[ -n '$endpoint' ]"

"$igtl" --help >"$work/help.txt"
check "bop-igtl --help names its options" "grep -q -- '--igtl-port' '$work/help.txt' && grep -q -- '--tool' '$work/help.txt'"
"$igtl" "$endpoint" --tool "a name longer than twenty" >"$work/badtool.txt" 2>&1
check "a tool name over 20 characters is refused, exit 2" "[ $? -eq 2 ] && grep -q 'tool must be 1 to 20' '$work/badtool.txt'"

"$igtl" "$endpoint" --igtl-port 0 --rate 30 --k0 2.5 --seconds 90 >"$work/igtl.log" 2>&1 &
ipid=$!
port=$(first_match "$work/igtl.log" 's/^OpenIGTLink listening on port \([0-9]*\).*/\1/p')
check "bop-igtl listens for OpenIGTLink" "[ -n '$port' ]"

value() { sed -n "s/^$1=//p" "$2" | tail -1; }
atleast() { $py -c "import sys; sys.exit(0 if float('${1:-nan}') >= float('$2') else 1)"; }

# The reference library's receiver: IMAGE and TRANSFORM read by the library (CRC checked).
bounded 20 "$work/receive.log" timeout -s INT 4 "$receive" 127.0.0.1 "$port"
check "the library's ReceiveClient reads the label IMAGE" \
  "grep -q 'Device Name *: BoP labels' '$work/receive.log' && grep -q 'Scalar Type *: 3' '$work/receive.log'"
check "... and the probe's TRANSFORM, and sees the POLYDATA" \
  "grep -q 'Receiving TRANSFORM' '$work/receive.log' && grep -q 'Receiving : POLYDATA' '$work/receive.log'"

bounded 60 "$work/check.txt" "$py" "$client" check --port "$port" --seconds 6 --press --press-above-mm 1.0
cat "$work/check.txt"
check "the label IMAGE comes once" "[ '$(value images "$work/check.txt")' = 1 ]"
check "the bag at >= 25 updates/s with 30 asked ($(value updates_per_s "$work/check.txt"))" \
  "atleast '$(value updates_per_s "$work/check.txt")' 25"
check "surface points carry Normals and Species" "[ '$(value point_data "$work/check.txt")' = 'Normals,Species' ]"
check ">= 98% of surface particles within one voxel of the image's surface ($(value within_one_voxel "$work/check.txt"))" \
  "atleast '$(value within_one_voxel "$work/check.txt")' 0.98"
before=$(value tip_clearance_before_mm "$work/check.txt") spread=$(value tip_clearance_unpressed_spread_mm "$work/check.txt")
pressed=$(value tip_clearance_pressed_mm "$work/check.txt")
check "the tool's TRANSFORM pushes the particles under the tip away (clearance $before -> $pressed mm; unpressed spread $spread)" \
  "$py -c 'import sys; b, s, p = (float(x) for x in (\"${before:-0}\", \"${spread:-9}\", \"${pressed:-0}\")); sys.exit(0 if p > b + 2 * s + 1.0 else 1)'"
check "the probe's reaction shows as the ProbeForce line ($(value force_line_mm "$work/check.txt") mm)" \
  "atleast '$(value force_line_mm "$work/check.txt")' 0.01"

for kind in version size crc type; do
  bounded 20 "$work/bad-$kind.txt" "$py" "$client" bad --port "$port" --kind "$kind"
done
check "a header of version 99 closes its connection, with the reason" \
  "[ '$(value closed "$work/bad-version.txt")' = 1 ] && grep -q 'header version 99, expected 1 or 2; connection closed' '$work/igtl.log'"
check "a body of 2^40 bytes is refused before it is read" \
  "[ '$(value closed "$work/bad-size.txt")' = 1 ] && grep -q 'announces a body of 1099511627776 bytes' '$work/igtl.log'"
check "a wrong CRC skips the message, the connection stays" \
  "[ '$(value closed "$work/bad-crc.txt")' = 0 ] && grep -q 'body CRC-64 does not match the header.s; message skipped' '$work/igtl.log'"
check "an unknown type is skipped, the connection stays" \
  "[ '$(value closed "$work/bad-type.txt")' = 0 ] && grep -q 'NOSUCHTYPE is not a type bop-igtl reads' '$work/igtl.log'"

"$py" "$client" idle --port "$port" --count 9 --seconds 12 >"$work/idle.txt" 2>&1 &
idle=$!
sleep 3
bounded 60 "$work/check2.txt" "$py" "$client" check --port "$port" --seconds 6  # the idle ones are full by now
check "with nine connections that never read, a reader still gets >= 25 updates/s ($(value updates_per_s "$work/check2.txt"))" \
  "[ '$(value idle_connections "$work/idle.txt")' = 9 ] && atleast '$(value updates_per_s "$work/check2.txt")' 25"
wait "$idle"

kill -INT "$ipid"
wait "$ipid"
check "bop-igtl stops on SIGINT with exit 0 and its counts" "[ $? -eq 0 ] && grep -q 'messages sent' '$work/igtl.log'"
kill -INT "$spid"
wait "$spid"
[[ $fail == 0 ]] || { echo "--- bop-igtl log"; tail -40 "$work/igtl.log"; }
exit $fail
