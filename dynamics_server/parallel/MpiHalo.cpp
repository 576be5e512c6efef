// The halo plan of a decomposed run (MpiExchange.hpp): copies of the neighbours' particles within
// a range of this subdomain, built in staged passes and refreshed along the same send lists.
#include "MpiExchange.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace bop::parallel {

void MpiExchange::buildHalo(const core::Particles& p, double range, core::Halo& halo) {
    halo = core::Halo{};
    stages_.clear();
    haloBytes_ = 0;
    particlesAtBuild_ = p.size();
    const core::Box mine = dec_.subdomain(comm_.coords());
    const auto sourcePos = [&](std::uint32_t s) { return s < p.size() ? p.pos[s] : halo.pos[s - p.size()]; };
    for (int a = 0; a < 3; ++a) {
        const int n = comm_.dims()[std::size_t(a)];
        if (n == 1) continue;
        Stage st;
        st.axis = a;
        const int c = comm_.coords()[std::size_t(a)];
        if (c == 0) st.lowerShift[a] = box_.size()[a];       // the lower neighbour lies across the periodic seam
        if (c == n - 1) st.upperShift[a] = -box_.size()[a];  // so does the upper one
        const std::size_t sources = p.size() + halo.size();
        if (sources >= std::numeric_limits<std::uint32_t>::max())
            throw std::runtime_error("halo: more than 2^32 particles and ghosts on one rank; use more ranks");
        for (std::uint32_t s = 0; s < std::uint32_t(sources); ++s) {
            const double x = sourcePos(s)[a];
            if (x < mine.lo[a] + range) st.toLower.push_back(s);
            if (x >= mine.hi[a] - range) st.toUpper.push_back(s);
        }
        const auto pack = [&](const std::vector<std::uint32_t>& list, const Eigen::Vector3d& shift) {
            std::vector<GhostRecord> out;
            out.reserve(list.size());
            for (std::uint32_t s : list) {
                const bool own = s < p.size();
                const std::size_t g = s - p.size();
                out.push_back({sourcePos(s) + shift, own ? p.normal[s] : halo.normal[g], own ? p.id[s] : halo.id[g],
                               own ? p.species[s] : halo.species[g]});
            }
            return out;
        };
        const auto append = [&](const std::vector<GhostRecord>& in) {
            for (const GhostRecord& g : in) {
                halo.pos.push_back(g.pos);
                halo.normal.push_back(g.normal);
                halo.species.push_back(std::uint8_t(g.species));
                halo.id.push_back(g.id);
            }
        };
        std::vector<GhostRecord> fromUpper, fromLower;
        const std::vector<GhostRecord> outLower = pack(st.toLower, st.lowerShift),
                                       outUpper = pack(st.toUpper, st.upperShift);
        comm_.sendRecv(outLower, comm_.lower(a), fromUpper, comm_.upper(a), tag(HaloBuildTag::ToLower, a));
        comm_.sendRecv(outUpper, comm_.upper(a), fromLower, comm_.lower(a), tag(HaloBuildTag::ToUpper, a));
        haloBytes_ += ((comm_.lower(a) == MPI_PROC_NULL ? 0 : outLower.size()) +
                       (comm_.upper(a) == MPI_PROC_NULL ? 0 : outUpper.size())) *
                      sizeof(GhostRecord);
        st.fromUpperAt = halo.size();
        st.fromUpperCount = fromUpper.size();
        append(fromUpper);
        st.fromLowerAt = halo.size();
        st.fromLowerCount = fromLower.size();
        append(fromLower);
        if (comm_.lower(a) == MPI_PROC_NULL) st.toLower.clear();  // nothing was sent there
        if (comm_.upper(a) == MPI_PROC_NULL) st.toUpper.clear();
        stages_.push_back(std::move(st));
    }
}

void MpiExchange::updateHalo(const core::Particles& p, core::Halo& halo) {
    if (!stages_.empty() && p.size() != particlesAtBuild_)
        throw std::logic_error("halo refresh: the particles changed since the plan was made");
    haloBytes_ = 0;
    for (const Stage& st : stages_) {
        const auto pack = [&](const std::vector<std::uint32_t>& list, const Eigen::Vector3d& shift,
                              std::vector<GhostRefresh>& out) {
            out.resize(list.size());
            GhostRefresh* o = out.data();
            for (std::uint32_t s : list) {
                const bool own = s < p.size();
                *o++ = {(own ? p.pos[s] : halo.pos[s - p.size()]) + shift,
                        own ? p.normal[s] : halo.normal[s - p.size()]};
            }
        };
        const auto store = [&](const std::vector<GhostRefresh>& in, std::size_t at, std::size_t count) {
            if (in.size() != count) throw std::runtime_error("halo refresh: a neighbour sent another ghost count");
            for (std::size_t k = 0; k < count; ++k) {
                halo.pos[at + k] = in[k].pos;
                halo.normal[at + k] = in[k].normal;
            }
        };
        pack(st.toLower, st.lowerShift, out_[0]);
        pack(st.toUpper, st.upperShift, out_[1]);
        comm_.sendRecv(out_[0], comm_.lower(st.axis), in_[0], comm_.upper(st.axis),
                       tag(HaloRefreshTag::ToLower, st.axis));
        comm_.sendRecv(out_[1], comm_.upper(st.axis), in_[1], comm_.lower(st.axis),
                       tag(HaloRefreshTag::ToUpper, st.axis));
        haloBytes_ += (out_[0].size() + out_[1].size()) * sizeof(GhostRefresh);
        store(in_[0], st.fromUpperAt, st.fromUpperCount);
        store(in_[1], st.fromLowerAt, st.fromLowerCount);
    }
}

void MpiExchange::shareGhostValues(const std::vector<double>& mine, std::vector<double>& ghosts) {
    std::size_t count = 0;
    if (!stages_.empty() && mine.size() != particlesAtBuild_)
        throw std::logic_error("ghost values: the particles changed since the plan was made");
    for (const Stage& st : stages_) count = std::max(count, st.fromLowerAt + st.fromLowerCount);
    ghosts.assign(count, 0.0);
    std::vector<GhostValue> out[2], in[2];
    for (const Stage& st : stages_) {
        const auto pack = [&](const std::vector<std::uint32_t>& list, std::vector<GhostValue>& o) {
            o.resize(list.size());
            for (std::size_t k = 0; k < list.size(); ++k) {
                const std::uint32_t s = list[k];
                o[k].value = s < mine.size() ? mine[s] : ghosts[s - mine.size()];
            }
        };
        const auto store = [&](const std::vector<GhostValue>& v, std::size_t at, std::size_t n) {
            if (v.size() != n) throw std::runtime_error("ghost values: a neighbour sent another ghost count");
            for (std::size_t k = 0; k < n; ++k) ghosts[at + k] = v[k].value;
        };
        pack(st.toLower, out[0]);
        pack(st.toUpper, out[1]);
        comm_.sendRecv(out[0], comm_.lower(st.axis), in[0], comm_.upper(st.axis), tag(GhostValueTag::ToLower, st.axis));
        comm_.sendRecv(out[1], comm_.upper(st.axis), in[1], comm_.lower(st.axis), tag(GhostValueTag::ToUpper, st.axis));
        store(in[0], st.fromUpperAt, st.fromUpperCount);
        store(in[1], st.fromLowerAt, st.fromLowerCount);
    }
}

}  // namespace bop::parallel
