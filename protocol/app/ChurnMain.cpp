// bop-churn: clients that come, misbehave and go, against a served run, while a well-behaved
// viewer watches it (scripts/bench/churn.sh; the ctest "net: ... churn"). Each of --clients
// clients connects its own DEALER socket, says Hello, sends a burst of --burst messages (valid
// probes and commands mixed with out-of-range values, garbage, cut buffers and foreign kinds),
// reads what comes back for a moment and leaves; --concurrency of them at a time. Meanwhile a
// viewer session takes every frame and the server's step rate from them. Before the churn, and
// after it once the server has forgotten the churned sessions (--settle), it reads the server's
// resident memory (--server-pid). Prints one line of key=value figures, then a summary.
#include "bop/common/ToolMain.hpp"
#include "client/ClientSession.hpp"
#include "codec/Codec.hpp"
#include "codec/MessageKind.hpp"
#include "command_generated.h"
#include "probe_generated.h"

#include <CLI/CLI.hpp>
#include <zmq.hpp>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <random>
#include <thread>

using namespace bop::protocol;
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

namespace {

double seconds(Clock::duration d) {
    return std::chrono::duration<double>(d).count();
}

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// The server's resident memory, MB (VmRSS); 0 without a pid.
double residentMb(int pid) {
    if (pid <= 0) return 0;
    std::ifstream in("/proc/" + std::to_string(pid) + "/status");
    for (std::string line; std::getline(in, line);)
        if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
    return 0;
}

// A viewer on its own thread: every frame, and the step rate the frames carry, by time.
class Watcher {
public:
    explicit Watcher(const std::string& endpoint) {
        ClientOptions o;
        o.clientName = "churn-watcher";
        session_ = std::make_unique<ClientSession>(o);
        scene_ = session_->connect(endpoint, 10s);
        thread_ = std::thread([this] { loop(); });
    }
    ~Watcher() {
        stop_ = true;
        thread_.join();
    }
    const SceneInfo& scene() const { return scene_; }
    // Step rates the frames carried between `from` and `to`, and the longest gap between frames there.
    std::pair<std::vector<double>, double> between(Clock::time_point from, Clock::time_point to) const {
        std::lock_guard lock(m_);
        std::vector<double> rates;
        double gap = 0;
        Clock::time_point last = from;
        for (const auto& [t, rate] : samples_)
            if (t >= from && t <= to) rates.push_back(rate), gap = std::max(gap, seconds(t - last)), last = t;
        return {rates, std::max(gap, seconds(to - last))};
    }

private:
    void loop() {
        while (!stop_) {
            session_->pollFeedback();  // keeps the session (a Hello a third of the timeout)
            if (const auto f = session_->receiveFrame(50ms)) {
                std::lock_guard lock(m_);
                samples_.emplace_back(Clock::now(), f->stats.stepRateHz);
            }
        }
    }
    std::unique_ptr<ClientSession> session_;
    SceneInfo scene_;
    std::thread thread_;
    std::atomic<bool> stop_{false};
    mutable std::mutex m_;
    std::vector<std::pair<Clock::time_point, double>> samples_;
};

Buffer finished(flatbuffers::FlatBufferBuilder& fbb) {
    return Buffer(fbb.GetBufferPointer(), fbb.GetBufferPointer() + fbb.GetSize());
}

// One message of a misbehaving client's burst: about a third valid, the rest refused.
Buffer burstMessage(std::mt19937& rng, const SceneInfo& scene, std::uint64_t seq) {
    std::uniform_real_distribution<double> u(0, 1);
    const Eigen::Vector3d at =
        scene.boxLo + (scene.boxHi - scene.boxLo).cwiseProduct(Eigen::Vector3d(u(rng), u(rng), u(rng)));
    const double huge[] = {
        1e300, -1e300, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(), -1e-3, 1e7};
    const double bad = huge[rng() % 6];
    flatbuffers::FlatBufferBuilder fbb;
    switch (rng() % 9) {
        case 0: {  // a valid probe, away from the bag (inactive)
            Probe p;
            p.seq = seq;
            p.position = at;
            return encodeProbe(p);
        }
        case 1: {  // a valid command that changes nothing: resume a running server
            Command c;
            c.requestId = seq;
            c.body = RunControl{RunAction::Resume, 1};
            return encodeCommand(c);
        }
        case 2: {  // a probe with one number out of range
            const bop::wire::Vec3 p(at.x(), rng() % 2 ? bad : at.y(), at.z());
            const double k0 = rng() % 2 ? bad : 1.0, k1 = rng() % 2 ? bad : 1.0;
            bop::wire::FinishProbeBuffer(fbb, bop::wire::CreateProbe(fbb, seq, 0, &p, true, k0, k1));
            return finished(fbb);
        }
        case 3: {  // a parameter out of range
            const char* names[] = {"lj", "co_normal", "co_planar", "drag_v", "drag_w", "k0", "k1"};
            const auto body = bop::wire::CreateSetParameterDirect(fbb, names[rng() % 7], 1, 1, bad).Union();
            bop::wire::FinishCommandBuffer(
                fbb, bop::wire::CreateCommand(fbb, seq, bop::wire::CommandBody::SetParameter, body));
            return finished(fbb);
        }
        case 4: {  // a seed far outside the box
            const bop::wire::Vec3 p(at.x(), at.y(), scene.boxHi.z() + 1e3);
            const auto body = bop::wire::CreateSeedParticle(fbb, 1, &p).Union();
            bop::wire::FinishCommandBuffer(
                fbb, bop::wire::CreateCommand(fbb, seq, bop::wire::CommandBody::SeedParticle, body));
            return finished(fbb);
        }
        case 5: {  // garbage
            Buffer b(1 + rng() % 300);
            for (auto& x : b) x = std::uint8_t(rng());
            return b;
        }
        case 6: {  // a valid probe cut short
            Buffer b = encodeProbe(Probe{});
            b.resize(rng() % b.size());
            return b;
        }
        case 7: {  // a valid message with one byte flipped
            Buffer b = encodeHello({});
            b[rng() % b.size()] ^= std::uint8_t(1 + rng() % 255);
            return b;
        }
        default:  // a message only a server sends
            return encodeFeedback(Feedback{});
    }
}

struct ChurnCounts {
    std::atomic<std::uint64_t> clients{0}, sent{0}, refusals{0}, replies{0}, scenes{0}, failed{0};
};

// One misbehaving client, start to end.
void churnOne(zmq::context_t& ctx, const std::string& endpoint, const SceneInfo& scene, int burst, std::mt19937& rng,
              ChurnCounts& counts) {
    zmq::socket_t s(ctx, zmq::socket_type::dealer);
    s.set(zmq::sockopt::linger, 0);
    s.set(zmq::sockopt::rcvtimeo, 20);
    s.connect(endpoint);
    s.send(zmq::buffer(encodeHello({})), zmq::send_flags::dontwait);
    for (int k = 0; k < burst; ++k) {
        const Buffer b = burstMessage(rng, scene, std::uint64_t(k + 1));
        s.send(zmq::buffer(b), zmq::send_flags::dontwait);
        ++counts.sent;
    }
    bool scened = false;
    for (const auto until = Clock::now() + 100ms; Clock::now() < until;) {  // what comes back, for a moment
        zmq::message_t m;
        if (!s.recv(m)) continue;
        const auto* p = static_cast<const std::uint8_t*>(m.data());
        const MessageKind kind = messageKind(p, m.size());
        if (kind == MessageKind::SceneInfo) scened = true, ++counts.scenes;
        if (kind == MessageKind::Refusal) ++counts.refusals;
        if (kind == MessageKind::CommandReply) ++counts.replies;
    }
    if (!scened) ++counts.failed;
    ++counts.clients;
}

int run(int argc, char** argv) {
    CLI::App app{
        "bop-churn: clients that connect, send a burst of mixed valid and invalid messages and leave, "
        "against a served run, while a viewer watches; prints the step rate, the server's memory and the "
        "refusals"};
    std::string endpoint;
    int clients = 1000, concurrency = 8, burst = 20, pid = 0;
    double baseline = 3, settle = 5;
    unsigned seed = 1;
    app.add_option("endpoint", endpoint, "the server's control endpoint, tcp://HOST:PORT")->required();
    app.add_option("--clients", clients, "misbehaving clients, one after another")->check(CLI::Range(1, 1000000));
    app.add_option("--concurrency", concurrency, "clients at a time")->check(CLI::Range(1, 256));
    app.add_option("--burst", burst, "messages each client sends")->check(CLI::Range(0, 10000));
    app.add_option("--baseline", baseline, "seconds of watching before the churn, s")->check(CLI::Range(0.5, 600.0));
    app.add_option("--settle", settle,
                   "seconds after the churn before memory is read again (longer than the "
                   "server's --session-timeout), s")
        ->check(CLI::Range(0.0, 600.0));
    app.add_option("--server-pid", pid, "the server's process, for its resident memory (VmRSS)");
    app.add_option("--seed", seed, "random seed of the bursts");
    CLI11_PARSE(app, argc, argv);

    Watcher watcher(endpoint);
    const SceneInfo scene = watcher.scene();
    const auto t0 = Clock::now();
    std::this_thread::sleep_for(std::chrono::duration<double>(baseline));
    const double rssBefore = residentMb(pid);
    const auto t1 = Clock::now();
    ChurnCounts counts;
    std::atomic<int> next{0};
    zmq::context_t ctx(1);
    std::vector<std::thread> workers;
    for (int w = 0; w < concurrency; ++w)
        workers.emplace_back([&, w] {
            std::mt19937 rng(seed * 7919u + unsigned(w));
            for (int k = next++; k < clients; k = next++) {
                churnOne(ctx, endpoint, scene, burst, rng, counts);
                if (counts.clients % 100 == 0)
                    std::fprintf(stderr, "bop-churn: %llu clients\n", (unsigned long long)counts.clients.load());
            }
        });
    for (auto& w : workers) w.join();
    const auto t2 = Clock::now();
    std::this_thread::sleep_for(std::chrono::duration<double>(settle));
    const double rssAfter = residentMb(pid);
    const auto t3 = Clock::now();
    const auto [before, gapBefore] = watcher.between(t0 + 500ms, t1);
    const auto [during, gapDuring] = watcher.between(t1, t2);
    const auto [after, gapAfter] = watcher.between(t2, t3);
    const double churnS = seconds(t2 - t1);
    std::printf(
        "clients=%llu seconds=%.2f clients_per_s=%.1f messages=%llu refusals_received=%llu replies=%llu "
        "no_scene=%llu steps_per_s_before=%.1f steps_per_s_during=%.1f steps_per_s_after=%.1f "
        "frames_during=%zu longest_frame_gap_s=%.3f rss_before_mb=%.2f rss_after_mb=%.2f\n",
        (unsigned long long)counts.clients.load(), churnS, double(counts.clients) / churnS,
        (unsigned long long)counts.sent.load(), (unsigned long long)counts.refusals.load(),
        (unsigned long long)counts.replies.load(), (unsigned long long)counts.failed.load(), median(before),
        median(during), median(after), during.size(), std::max({gapBefore, gapDuring, gapAfter}), rssBefore, rssAfter);
    std::printf(
        "bop-churn: %llu clients in %.1f s sent %llu messages; the watching viewer took %zu frames meanwhile "
        "(longest gap %.3f s); the server's step rate %.0f before, %.0f during, %.0f after; its memory %.1f MB "
        "before, %.1f MB after\n",
        (unsigned long long)counts.clients.load(), churnS, (unsigned long long)counts.sent.load(), during.size(),
        std::max({gapBefore, gapDuring, gapAfter}), median(before), median(during), median(after), rssBefore, rssAfter);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    return bop::runTool("bop-churn", [&] { return run(argc, argv); });
}
