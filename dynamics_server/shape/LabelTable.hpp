#pragma once
// Names and colours of a segmentation's labels, from the label files segmentation tools write:
// an ITK-SNAP label description file (IDX R G B A VIS MSH "LABEL" per line, R G B in 0-255, A in
// 0-1) or a 3D Slicer colour table (index name R G B A per line, all 0-255). '#' starts a comment.
#include <array>
#include <map>
#include <string>

namespace bop::shape {

struct LabelEntry {
    std::string name;               // as the file gives it (may hold spaces)
    std::array<float, 3> colour{};  // r, g, b in [0, 1]
};

// Label value -> entry. Throws bop::Error naming the file and line for a line of neither form.
std::map<int, LabelEntry> readLabelTable(const std::string& path);

}  // namespace bop::shape
