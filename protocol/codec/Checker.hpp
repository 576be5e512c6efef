#pragma once
// Internal to the codecs: collects the first broken rule of a message as a Validation.
#include "codec/Validate.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

namespace bop::protocol::detail {

class Checker {
public:
    explicit Checker(const char* messageName) : name_(messageName) {}

    bool ok() const { return result_.ok(); }
    const Validation& result() const { return result_; }

    // Records the failure if it is the first; returns false so callers can `return c.fail(...)`.
    bool fail(DecodeError e, const char* field, const std::string& what) {
        if (result_.ok()) {
            result_.error = e;
            result_.message = std::string(name_) + "." + field + ": " + what;
        }
        return false;
    }
    bool require(bool cond, DecodeError e, const char* field, const std::string& what) {
        return cond || fail(e, field, what);
    }
    bool finite(double v, const char* field) {
        return std::isfinite(v) || fail(DecodeError::NotFinite, field, "not a finite number");
    }
    bool finite(const Eigen::Vector3d& v, const char* field) {
        return v.allFinite() || fail(DecodeError::NotFinite, field, "not a finite vector");
    }
    // A finite number in [lo, hi]; the message names the range (the valid ranges: Ranges.hpp).
    bool within(double v, double lo, double hi, const char* field) {
        return finite(v, field) && require(v >= lo && v <= hi, DecodeError::OutOfRange, field,
                                           number(v) + " outside " + number(lo) + ".." + number(hi));
    }
    // Every component finite and of magnitude at most `bound`.
    bool within(const Eigen::Vector3d& v, double bound, const char* field) {
        return finite(v, field) && require(v.cwiseAbs().maxCoeff() <= bound, DecodeError::OutOfRange, field,
                                           "a component of magnitude " + number(v.cwiseAbs().maxCoeff()) +
                                               " (at most " + number(bound) + ")");
    }
    static std::string number(double v) {
        char text[32];
        std::snprintf(text, sizeof text, "%.6g", v);
        return text;
    }
    bool finiteArray(const float* p, std::size_t n, const char* field) {
        // A float is infinite or NaN when its exponent bits are all set. Or-ing that test over
        // the array has no early exit and vectorises; the element is looked for only on failure.
        std::uint32_t bad = 0;
        for (std::size_t i = 0; i < n; ++i) {
            std::uint32_t bits;
            std::memcpy(&bits, p + i, sizeof bits);
            bad |= std::uint32_t((bits & 0x7f800000u) == 0x7f800000u);
        }
        if (bad == 0) return true;
        std::size_t i = 0;
        while (std::isfinite(p[i])) ++i;
        return fail(DecodeError::NotFinite, field, "element " + std::to_string(i) + " not finite");
    }
    // Every byte of a species array in [lowest, highest]; the offender is looked for only on failure.
    bool speciesArray(const std::uint8_t* s, std::size_t n, int lowest, int highest, const char* field) {
        std::uint8_t lo = 255, hi = 0;
        for (std::size_t i = 0; i < n; ++i) lo = std::min(lo, s[i]), hi = std::max(hi, s[i]);
        if (n == 0 || (lo >= lowest && hi <= highest)) return true;
        std::size_t i = 0;
        while (s[i] >= lowest && s[i] <= highest) ++i;
        return species(s[i], lowest, highest, field);
    }
    bool maxBytes(const std::string& s, std::size_t cap, const char* field) {
        return s.size() <= cap ||
               fail(DecodeError::BadLength, field, std::to_string(s.size()) + " bytes, at most " + std::to_string(cap));
    }
    // A species number in [lowest, highest]: lowest 1 for a particle's species, 0 where 0 means none.
    bool species(int s, int lowest, int highest, const char* field) {
        return (s >= lowest && s <= highest) || fail(DecodeError::OutOfRange, field,
                                                     "species " + std::to_string(s) + " outside " +
                                                         std::to_string(lowest) + ".." + std::to_string(highest));
    }

private:
    const char* name_;
    Validation result_;
};

// Quantisation bounds of a frame: finite, lo < hi on every axis, within kMaxBoundMagnitude.
bool checkQuantBounds(Checker& c, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);

}  // namespace bop::protocol::detail
