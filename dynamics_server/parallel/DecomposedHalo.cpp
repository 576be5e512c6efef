// The halo: copies of the neighbours' particles within a range of this subdomain, built in
// staged passes and refreshed along the same send lists (see DecomposedSimulation.hpp).
#include "DecomposedSimulation.hpp"

#include "Packing.hpp"

#include <limits>
#include <stdexcept>

namespace bop::parallel {
namespace {

constexpr int kGhostFields = 8;   // pos 3, normal 3, species, id
constexpr int kUpdateFields = 6;  // pos 3, normal 3

}  // namespace

void DecomposedSimulation::buildHalo(double range) {
    halo_ = core::Halo{};
    stages_.clear();
    haloBytes_ = 0;
    const core::Box& box = model_->box;
    const core::Box& mine = sub_.box;
    for (int a = 0; a < 3; ++a) {
        const int n = comm_.dims()[std::size_t(a)];
        if (n == 1) continue;
        Stage st;
        st.axis = a;
        const int c = comm_.coords()[std::size_t(a)];
        if (c == 0) st.lowerShift[a] = box.size()[a];       // lower neighbour lies across the periodic seam
        if (c == n - 1) st.upperShift[a] = -box.size()[a];  // so does the upper one
        const std::size_t sources = p_.size() + halo_.size();
        if (sources >= std::numeric_limits<std::uint32_t>::max())
            throw std::runtime_error("halo: more than 2^32 particles and ghosts on one rank; use more ranks");
        for (std::uint32_t s = 0; s < std::uint32_t(sources); ++s) {
            const double x = sourcePos(s)[a];
            if (x < mine.lo[a] + range) st.toLower.push_back(s);
            if (x >= mine.hi[a] - range) st.toUpper.push_back(s);
        }
        const auto pack = [&](const std::vector<std::uint32_t>& list, const Eigen::Vector3d& shift) {
            std::vector<double> out;
            out.reserve(list.size() * kGhostFields);
            for (std::uint32_t s : list) {
                const bool own = s < p_.size();
                const Eigen::Vector3d x = sourcePos(s) + shift;
                const Eigen::Vector3d nrm = own ? p_.normal[s] : halo_.normal[s - p_.size()];
                const double species = own ? p_.species[s] : halo_.species[s - p_.size()];
                const std::uint64_t id = own ? p_.id[s] : halo_.id[s - p_.size()];
                out.insert(out.end(), {x.x(), x.y(), x.z(), nrm.x(), nrm.y(), nrm.z(), species, idBits(id)});
            }
            return out;
        };
        const auto append = [&](const std::vector<double>& in) {
            for (std::size_t k = 0; k + kGhostFields <= in.size(); k += kGhostFields) {
                halo_.pos.emplace_back(in[k], in[k + 1], in[k + 2]);
                halo_.normal.emplace_back(in[k + 3], in[k + 4], in[k + 5]);
                halo_.species.push_back(std::uint8_t(in[k + 6]));
                halo_.id.push_back(idOf(in[k + 7]));
            }
        };
        std::vector<double> fromUpper, fromLower;
        const std::vector<double> outLower = pack(st.toLower, st.lowerShift), outUpper = pack(st.toUpper, st.upperShift);
        comm_.sendRecv(outLower, comm_.lower(a), fromUpper, comm_.upper(a), 200 + 4 * a);
        comm_.sendRecv(outUpper, comm_.upper(a), fromLower, comm_.lower(a), 202 + 4 * a);
        haloBytes_ += ((comm_.lower(a) == MPI_PROC_NULL ? 0 : outLower.size()) +
                       (comm_.upper(a) == MPI_PROC_NULL ? 0 : outUpper.size())) * sizeof(double);
        st.fromUpperAt = halo_.size();
        st.fromUpperCount = fromUpper.size() / kGhostFields;
        append(fromUpper);
        st.fromLowerAt = halo_.size();
        st.fromLowerCount = fromLower.size() / kGhostFields;
        append(fromLower);
        if (comm_.lower(a) == MPI_PROC_NULL) st.toLower.clear();  // nothing was sent there
        if (comm_.upper(a) == MPI_PROC_NULL) st.toUpper.clear();
        stages_.push_back(std::move(st));
    }
}

void DecomposedSimulation::updateHalo() {
    haloBytes_ = 0;
    for (const Stage& st : stages_) {
        const auto pack = [&](const std::vector<std::uint32_t>& list, const Eigen::Vector3d& shift, std::vector<double>& out) {
            out.resize(list.size() * kUpdateFields);
            double* o = out.data();
            for (std::uint32_t s : list) {
                const Eigen::Vector3d x = sourcePos(s) + shift;
                const Eigen::Vector3d& nrm = s < p_.size() ? p_.normal[s] : halo_.normal[s - p_.size()];
                *o++ = x.x(); *o++ = x.y(); *o++ = x.z(); *o++ = nrm.x(); *o++ = nrm.y(); *o++ = nrm.z();
            }
        };
        const auto store = [&](const std::vector<double>& in, std::size_t at, std::size_t count) {
            if (in.size() != count * kUpdateFields) throw std::runtime_error("halo update: neighbour sent another ghost count");
            for (std::size_t k = 0; k < count; ++k) {
                halo_.pos[at + k] = Eigen::Vector3d(in[6 * k], in[6 * k + 1], in[6 * k + 2]);
                halo_.normal[at + k] = Eigen::Vector3d(in[6 * k + 3], in[6 * k + 4], in[6 * k + 5]);
            }
        };
        pack(st.toLower, st.lowerShift, out_[0]);
        pack(st.toUpper, st.upperShift, out_[1]);
        comm_.sendRecv(out_[0], comm_.lower(st.axis), in_[0], comm_.upper(st.axis), 300 + 4 * st.axis);
        comm_.sendRecv(out_[1], comm_.upper(st.axis), in_[1], comm_.lower(st.axis), 302 + 4 * st.axis);
        haloBytes_ += (out_[0].size() + out_[1].size()) * sizeof(double);
        store(in_[0], st.fromUpperAt, st.fromUpperCount);
        store(in_[1], st.fromLowerAt, st.fromLowerCount);
    }
}

}  // namespace bop::parallel
