#include "bop/common/DistanceTransform.hpp"

#include <algorithm>
#include <climits>
#include <cstddef>
#include <stdexcept>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace {
int teamSize(int threads) {
#ifdef _OPENMP
    return threads > 0 ? threads : omp_get_max_threads();
#else
    (void)threads;
    return 1;
#endif
}
}  // namespace

namespace bop {
namespace {

constexpr std::int32_t kInf = INT32_MAX;

// Nearest site along one row (x), two scans. Writes squared distance and the site's label.
void rowPass(int n, const std::int32_t* labelIn, std::int32_t* dist2, std::int32_t* labelOut) {
    int last = -1;
    for (int i = 0; i < n; ++i) {
        if (labelIn[i] != kNoSite) last = i;
        if (last >= 0) {
            dist2[i] = (i - last) * (i - last);
            labelOut[i] = labelIn[last];
        } else {
            dist2[i] = kInf;
            labelOut[i] = kNoSite;
        }
    }
    int next = -1;
    for (int i = n - 1; i >= 0; --i) {
        if (labelIn[i] != kNoSite) next = i;
        if (next >= 0) {
            const std::int32_t d = (next - i) * (next - i);
            if (d < dist2[i]) {
                dist2[i] = d;
                labelOut[i] = labelIn[next];
            }
        }
    }
}

struct Envelope {
    std::vector<int> v;                 // parabola apexes (sample positions)
    std::vector<std::int64_t> F;        // f[v] + v^2 of each apex
    std::vector<std::int32_t> fv, lab;  // f and label of each apex
    explicit Envelope(int n) : v(n), F(n), fv(n), lab(n) {}
};

// Lower envelope of parabolas along one line of n samples; f and lab are the line's current
// squared distances and labels, overwritten with the result (unit spacing). Integer arithmetic
// throughout: a parabola is dropped when the new one overtakes it no later than it overtook its
// predecessor, compared by cross-multiplication instead of division.
void envelopePass(int n, Envelope& e, std::int32_t* f, std::int32_t* lab) {
    int k = -1;
    for (int q = 0; q < n; ++q) {
        if (f[q] == kInf) continue;
        const std::int64_t Fq = std::int64_t(f[q]) + std::int64_t(q) * q;
        while (k >= 1) {
            // s(q, v_k) <= s(v_k, v_{k-1})  with  s(a, b) = (F_a - F_b) / (2 (a - b))
            const int vk = e.v[k], vp = e.v[k - 1];
            if ((Fq - e.F[k]) * (vk - vp) <= (e.F[k] - e.F[k - 1]) * (q - vk))
                --k;
            else
                break;
        }
        ++k;
        e.v[k] = q;
        e.F[k] = Fq;
        e.fv[k] = f[q];
        e.lab[k] = lab[q];
    }
    if (k < 0) return;  // no finite sample: the line stays at infinity
    int j = 0;
    for (int p = 0; p < n; ++p) {
        // Move to the next parabola while it is at least as low at p: F_{j+1} - F_j <= 2 p (v_{j+1} - v_j).
        while (j < k && e.F[j + 1] - e.F[j] <= 2 * std::int64_t(p) * (e.v[j + 1] - e.v[j])) ++j;
        const int vj = e.v[j];
        f[p] = (p - vj) * (p - vj) + e.fv[j];
        lab[p] = e.lab[j];
    }
}

// Transform every line along an axis with the given element stride. Lines are grouped in
// blocks of consecutive x so that gathers and scatters touch whole cache lines.
void axisPass(const Dims& dims, int axis, std::int32_t* dist2, std::int32_t* label, int threads) {
    const int n = axis == 1 ? dims.ny : dims.nz;
    const std::size_t stride = axis == 1 ? std::size_t(dims.nx) : std::size_t(dims.nx) * dims.ny;
    const int other = axis == 1 ? dims.nz : dims.ny;  // the axis that is neither x nor `axis`
    constexpr int kBlock = 16;
    const int xBlocks = (dims.nx + kBlock - 1) / kBlock;
    const long long jobs = (long long)xBlocks * other;
#pragma omp parallel num_threads(teamSize(threads))
    {
        Envelope env(n);
        std::vector<std::int32_t> bufF(std::size_t(kBlock) * n), bufL(std::size_t(kBlock) * n);
#pragma omp for schedule(static)
        for (long long job = 0; job < jobs; ++job) {
            const int o = int(job / xBlocks);
            const int x0 = int(job % xBlocks) * kBlock;
            const int bw = std::min(kBlock, dims.nx - x0);
            const std::size_t base = axis == 1 ? dims.index(x0, 0, o) : dims.index(x0, o, 0);
            for (int p = 0; p < n; ++p) {
                const std::size_t row = base + std::size_t(p) * stride;
                for (int b = 0; b < bw; ++b) {
                    bufF[std::size_t(b) * n + p] = dist2[row + b];
                    bufL[std::size_t(b) * n + p] = label[row + b];
                }
            }
            for (int b = 0; b < bw; ++b) envelopePass(n, env, &bufF[std::size_t(b) * n], &bufL[std::size_t(b) * n]);
            for (int p = 0; p < n; ++p) {
                const std::size_t row = base + std::size_t(p) * stride;
                for (int b = 0; b < bw; ++b) {
                    dist2[row + b] = bufF[std::size_t(b) * n + p];
                    label[row + b] = bufL[std::size_t(b) * n + p];
                }
            }
        }
    }
}

}  // namespace

void exactDistanceTransform(const Dims& dims, std::vector<std::int32_t>& feature, std::vector<std::int32_t>& dist2,
                            int threads) {
    if (feature.size() != dims.count()) throw std::invalid_argument("exactDistanceTransform: size");
    const long long maxD2 = 3LL * std::max({dims.nx, dims.ny, dims.nz}) * std::max({dims.nx, dims.ny, dims.nz});
    if (maxD2 >= kInf) throw std::invalid_argument("exactDistanceTransform: grid too large for int32 distances");
    dist2.assign(dims.count(), kInf);
    const long long rows = (long long)dims.ny * dims.nz;
#pragma omp parallel num_threads(teamSize(threads))
    {
        std::vector<std::int32_t> in(dims.nx);
#pragma omp for schedule(static)
        for (long long r = 0; r < rows; ++r) {
            std::int32_t* lab = feature.data() + std::size_t(r) * dims.nx;
            std::copy(lab, lab + dims.nx, in.begin());
            rowPass(dims.nx, in.data(), dist2.data() + std::size_t(r) * dims.nx, lab);
        }
    }
    if (dims.ny > 1) axisPass(dims, 1, dist2.data(), feature.data(), threads);
    if (dims.nz > 1) axisPass(dims, 2, dist2.data(), feature.data(), threads);
}

}  // namespace bop
