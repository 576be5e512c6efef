#include "scene/Controls.hpp"

namespace bop::viz {
namespace {

protocol::Command parameter(const std::string& name, int a, int b, double value) {
    return {0, protocol::SetParameter{name, a, b, value}};
}

// Matrix entries (row a receives from b, both 1-based) that differ between `now` and `sent`.
void changedWeights(const char* name, std::vector<double>& now, std::vector<double>& sent, int n,
                    std::vector<protocol::Command>& out) {
    for (int a = 1; a <= n; ++a)
        for (int b = 1; b <= n; ++b) {
            const std::size_t k = std::size_t(a - 1) * std::size_t(n) + std::size_t(b - 1);
            if (now[k] != sent[k]) out.push_back(parameter(name, a, b, now[k])), sent[k] = now[k];
        }
}

}  // namespace

Controls::Controls(const protocol::SceneInfo& scene) : n_(int(scene.species.size())) {
    const std::size_t n = std::size_t(n_);
    now = scene.tunables;
    const auto fill = [](std::vector<double>& v, std::size_t size, double value) {
        if (v.size() != size) v.assign(size, value);
    };
    fill(now.lj, n * n, 1.0);
    fill(now.coNormal, n * n, 1.0);
    fill(now.coPlanar, n * n, 1.0);
    fill(now.dragV, n, 0.0);
    fill(now.dragW, n, 0.0);
    sent_ = now;
}

std::vector<protocol::Command> Controls::commands() {
    std::vector<protocol::Command> out;
    changedWeights("lj", now.lj, sent_.lj, n_, out);
    changedWeights("co_normal", now.coNormal, sent_.coNormal, n_, out);
    changedWeights("co_planar", now.coPlanar, sent_.coPlanar, n_, out);
    for (int a = 1; a <= n_; ++a) {
        const std::size_t k = std::size_t(a - 1);
        if (now.dragV[k] != sent_.dragV[k])
            out.push_back(parameter("drag_v", a, 0, now.dragV[k])), sent_.dragV[k] = now.dragV[k];
        if (now.dragW[k] != sent_.dragW[k])
            out.push_back(parameter("drag_w", a, 0, now.dragW[k])), sent_.dragW[k] = now.dragW[k];
    }
    if (now.k0 != sent_.k0) out.push_back(parameter("k0", 0, 0, now.k0)), sent_.k0 = now.k0;
    if (now.k1 != sent_.k1) out.push_back(parameter("k1", 0, 0, now.k1)), sent_.k1 = now.k1;
    return out;
}

protocol::Command seedCommand(int species, const Eigen::Vector3d& position) {
    return {0, protocol::SeedParticle{species, position}};
}

protocol::Command cutCommand(const Eigen::Vector3d& from, const Eigen::Vector3d& to, double radius) {
    return {0, protocol::Cut{from, to, radius}};
}

protocol::Command birthCommand(int species, bool on) {
    return {0, protocol::SetBirth{species, on}};
}

protocol::Command runCommand(protocol::RunAction action, std::uint32_t steps) {
    return {0, protocol::RunControl{action, steps}};
}

protocol::Command recordCommand(bool start, const std::string& fileName) {
    return {0, protocol::Record{start, fileName}};
}

}  // namespace bop::viz
