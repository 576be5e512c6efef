#pragma once
// Hand-made client messages for the hardening tests: built straight with the FlatBuffers builders,
// without the encoders (which refuse what these carry), and the table of every number a client
// sends just outside its valid range, as NaN, infinite and huge (docs/protocol.md "Valid ranges").
#include "codec/Codec.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace bop::test::hostile {

using protocol::Buffer;

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
inline constexpr double kInf = std::numeric_limits<double>::infinity();

Buffer probeMessage(const Eigen::Vector3d& x, double k0 = 1, double k1 = 1, float rateHz = 0, float p99Us = 0,
                    const Eigen::Vector3d& rendered = Eigen::Vector3d::Zero(), std::uint64_t seq = 9);
Buffer helloMessage(float rateHz);
Buffer seedMessage(int species, const Eigen::Vector3d& x);
Buffer birthMessage(int species);
Buffer parameterMessage(const char* name, double value, int a = 1, int b = 1);
Buffer singleStepMessage(std::uint32_t steps);
Buffer mapRequestMessage(std::uint64_t offset, std::uint32_t length);

struct Case {
    const char* what;
    Buffer message;
    const char* field;  // the refusal's reason names it
};
// Every field a client sends, out of its range for `scene` (2 species or more).
std::vector<Case> outOfRange(const protocol::SceneInfo& scene);

}  // namespace bop::test::hostile
