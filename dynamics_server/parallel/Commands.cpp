#include "Commands.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace bop::parallel {
namespace {

constexpr std::size_t kProbeFields = 7;   // kind, active, x, y, z, k0, k1
constexpr std::size_t kDragFields = 4;    // kind, species, beta_v, beta_tau
constexpr std::size_t kSeedFields = 5;    // kind, species, x, y, z
constexpr std::size_t kBirthFields = 3;   // kind, species, on
constexpr std::size_t kWeightFields = 5;  // kind, table, species, other, value

}  // namespace

void encode(const Command& c, std::vector<double>& out) {
    if (c.kind == Command::Kind::Probe) {
        const auto& p = c.probe;
        out.insert(out.end(), {double(int(c.kind)), p.active ? 1.0 : 0.0, p.position.x(), p.position.y(),
                               p.position.z(), p.params.k0, p.params.k1});
    } else if (c.kind == Command::Kind::Drag) {
        out.insert(out.end(), {double(int(c.kind)), double(c.species), c.dragV, c.dragW});
    } else if (c.kind == Command::Kind::Seed) {
        out.insert(out.end(), {double(int(c.kind)), double(c.species), c.position.x(), c.position.y(), c.position.z()});
    } else if (c.kind == Command::Kind::Birth) {
        out.insert(out.end(), {double(int(c.kind)), double(c.species), c.on ? 1.0 : 0.0});
    } else {
        out.insert(out.end(), {double(int(c.kind)), double(int(c.table)), double(c.species), double(c.other), c.value});
    }
}

std::vector<Command> decode(const std::vector<double>& in) {
    std::vector<Command> out;
    for (std::size_t k = 0; k < in.size();) {
        Command c;
        const double kind = in[k];
        const auto need = [&](std::size_t n, const char* what) {
            if (k + n > in.size())
                throw std::invalid_argument(std::string("command array: a ") + what + " command needs " +
                                            std::to_string(n) + " values at position " + std::to_string(k) + ", " +
                                            std::to_string(in.size() - k) + " left");
        };
        if (kind == double(int(Command::Kind::Probe))) {
            need(kProbeFields, "probe");
            c.kind = Command::Kind::Probe;
            c.probe.active = in[k + 1] != 0;
            c.probe.position = Eigen::Vector3d(in[k + 2], in[k + 3], in[k + 4]);
            c.probe.params = {in[k + 5], in[k + 6]};
            k += kProbeFields;
        } else if (kind == double(int(Command::Kind::Drag))) {
            need(kDragFields, "drag");
            c.kind = Command::Kind::Drag;
            c.species = int(in[k + 1]);
            c.dragV = in[k + 2];
            c.dragW = in[k + 3];
            k += kDragFields;
        } else if (kind == double(int(Command::Kind::Seed))) {
            need(kSeedFields, "seed");
            c.kind = Command::Kind::Seed;
            c.species = int(in[k + 1]);
            c.position = Eigen::Vector3d(in[k + 2], in[k + 3], in[k + 4]);
            k += kSeedFields;
        } else if (kind == double(int(Command::Kind::Birth))) {
            need(kBirthFields, "birth");
            c.kind = Command::Kind::Birth;
            c.species = int(in[k + 1]);
            c.on = in[k + 2] != 0;
            k += kBirthFields;
        } else if (kind == double(int(Command::Kind::Weight))) {
            need(kWeightFields, "weight");
            c.kind = Command::Kind::Weight;
            const double table = in[k + 1];
            if (table != 0 && table != 1 && table != 2)
                throw std::invalid_argument("command array: weight table " + std::to_string(table) + " at position " +
                                            std::to_string(k + 1) +
                                            ", expected 0 (LJ), 1 (co-normal) or 2 (co-planar)");
            c.table = Command::Table(int(table));
            c.species = int(in[k + 2]);
            c.other = int(in[k + 3]);
            c.value = in[k + 4];
            k += kWeightFields;
        } else {
            throw std::invalid_argument("command array: unknown command kind " + std::to_string(kind) +
                                        " at position " + std::to_string(k));
        }
        out.push_back(c);
    }
    return out;
}

}  // namespace bop::parallel
