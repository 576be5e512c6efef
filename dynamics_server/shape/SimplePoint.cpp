#include "SimplePoint.hpp"

#include <cstdlib>

namespace bop::shape {
namespace {

struct Offset {
    int x, y, z;
};

constexpr Offset offsetOf(int s) {
    return {s % 3 - 1, s / 3 % 3 - 1, s / 9 - 1};
}

// Number of components among the positions `member` holds, two positions joined when their
// offsets differ by at most 1 on every axis (26-adjacency) or by 1 on one axis (6-adjacency);
// with `mustTouchFace`, only components holding a face neighbour of the centre are counted.
template <class Member>
int components(const Member& member, bool sixAdjacent, bool mustTouchFace) {
    std::array<bool, 27> seen{};
    int count = 0;
    for (int s = 0; s < 27; ++s) {
        if (!member(s) || seen[std::size_t(s)]) continue;
        std::array<int, 27> stack{};
        int top = 0;
        stack[std::size_t(top++)] = s;
        seen[std::size_t(s)] = true;
        bool touchesFace = false;
        while (top > 0) {
            const int a = stack[std::size_t(--top)];
            const Offset oa = offsetOf(a);
            touchesFace |= std::abs(oa.x) + std::abs(oa.y) + std::abs(oa.z) == 1;
            for (int b = 0; b < 27; ++b) {
                if (seen[std::size_t(b)] || !member(b)) continue;
                const Offset ob = offsetOf(b);
                const int dx = std::abs(oa.x - ob.x), dy = std::abs(oa.y - ob.y), dz = std::abs(oa.z - ob.z);
                const bool adjacent = sixAdjacent ? dx + dy + dz == 1 : dx <= 1 && dy <= 1 && dz <= 1;
                if (!adjacent) continue;
                seen[std::size_t(b)] = true;
                stack[std::size_t(top++)] = b;
            }
        }
        count += !mustTouchFace || touchesFace;
    }
    return count;
}

}  // namespace

bool isSimplePoint(const std::array<bool, 27>& object) {
    const auto objectNeighbour = [&](int s) { return s != 13 && object[std::size_t(s)]; };
    if (components(objectNeighbour, false, false) != 1) return false;
    const auto backgroundIn18 = [&](int s) {
        const Offset o = offsetOf(s);
        return s != 13 && std::abs(o.x) + std::abs(o.y) + std::abs(o.z) <= 2 && !object[std::size_t(s)];
    };
    return components(backgroundIn18, true, true) == 1;
}

}  // namespace bop::shape
