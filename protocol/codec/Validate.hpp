#pragma once
// Checks of the plain message structs: the semantic rules every decoder applies after reading a
// verified buffer, and every encoder before writing one. The first rule broken is reported.
#include "codec/DecodeResult.hpp"
#include "codec/Messages.hpp"

#include <string>

namespace bop::protocol {

struct Validation {
    DecodeError error = DecodeError::None;
    std::string message;  // "<Message>.<field>: <problem>"
    bool ok() const { return error == DecodeError::None; }
};

Validation validate(const Hello& m);
Validation validate(const SceneInfo& m);
Validation validate(const Probe& m);
Validation validate(const Feedback& m);
Validation validate(const Command& m);
Validation validate(const CommandReply& m);
Validation validate(const MapRequest& m);
Validation validate(const MapChunk& m);
Validation validate(const MapEditsRequest& m);
Validation validate(const MapEdits& m);
Validation validate(const Refusal& m);
// Array lengths (positions 3 x count, normals 0 or 3 x count, ids 0 or count), chunk index and
// count, particle range within the frame, finite numbers, species numbers, quantisation bounds.
Validation validate(const StateFrame& m, const FrameLimits& limits = {});

}  // namespace bop::protocol
