#pragma once
// "x,y,z" from a command line as a 3-vector; bop::Error naming the option otherwise.
#include "bop/common/Error.hpp"

#include <Eigen/Core>

#include <sstream>
#include <string>

namespace bop {

inline Eigen::Vector3d parseVector3(const std::string& text, const std::string& option) {
    std::istringstream in(text);
    Eigen::Vector3d p;
    char c1 = 0, c2 = 0;
    if (!(in >> p.x() >> c1 >> p.y() >> c2 >> p.z()) || c1 != ',' || c2 != ',' || !p.allFinite() || !in.eof())
        throw Error(option, "expected x,y,z, got '" + text + "'");
    return p;
}

}  // namespace bop
