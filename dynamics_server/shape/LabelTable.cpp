#include "LabelTable.hpp"

#include "bop/common/Error.hpp"

#include <fstream>
#include <sstream>

namespace bop::shape {
namespace {

bool colourByte(double v) {
    return v >= 0 && v <= 255;
}

}  // namespace

std::map<int, LabelEntry> readLabelTable(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw Error(path, "cannot open the label table");
    std::map<int, LabelEntry> out;
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
        if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
        if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
        const auto bad = [&](const std::string& why) {
            throw Error(path, "line " + std::to_string(number) + ": " + why +
                                  "; expected an ITK-SNAP label line (IDX R G B A VIS MSH \"LABEL\") or a 3D Slicer "
                                  "colour-table line (index name R G B A)");
        };
        std::istringstream s(line);
        long long label = 0;
        if (!(s >> label) || label < 0) bad("no label number");
        LabelEntry e;
        double r = 0, g = 0, b = 0, a = 0;
        if (const auto quote = line.find('"'); quote != std::string::npos) {  // ITK-SNAP
            const auto end = line.find('"', quote + 1);
            if (end == std::string::npos) bad("an unclosed quote");
            int visible = 0, mesh = 0;
            if (!(s >> r >> g >> b >> a >> visible >> mesh)) bad("too few numbers before the name");
            e.name = line.substr(quote + 1, end - quote - 1);
        } else {  // Slicer
            if (!(s >> e.name >> r >> g >> b >> a)) bad("too few fields");
        }
        if (!colourByte(r) || !colourByte(g) || !colourByte(b)) bad("a colour outside 0-255");
        if (out.count(int(label))) bad("label " + std::to_string(label) + " given twice");
        e.colour = {float(r / 255), float(g / 255), float(b / 255)};
        out[int(label)] = e;
    }
    return out;
}

}  // namespace bop::shape
