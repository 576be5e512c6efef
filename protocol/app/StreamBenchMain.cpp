// bop-stream-bench: one client's view of a served run, for scripts/bench/stream.sh.
//   frames ENDPOINT      frames/s and MB/s received for --seconds (after --pause: the same state
//                        streamed at the server's frame rate, so the stream alone is measured)
//   probe ENDPOINT       probe -> feedback round trips at --hz (1 kHz): p50, p99, max in ms
//                        (over ZeroMQ, or as datagrams with --udp)
//   rate ENDPOINT        the server's step rate (median of what frames carry) over --seconds
//   stuck ENDPOINT       a subscriber that never reads, for --seconds
#include "bop/common/ToolMain.hpp"
#include "client/ClientSession.hpp"

#include <CLI/CLI.hpp>
#include <zmq.hpp>

#include <algorithm>
#include <cstdio>
#include <map>
#include <thread>

using namespace bop::protocol;
using Clock = std::chrono::steady_clock;

namespace {

double seconds(Clock::duration d) {
    return std::chrono::duration<double>(d).count();
}

double percentile(std::vector<double> v, double q) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, std::size_t(q * double(v.size() - 1) + 0.5))];
}

int frames(ClientSession& c, double secs, bool pause) {
    if (pause) {
        Command cmd;
        cmd.requestId = 1;
        cmd.body = RunControl{RunAction::Pause, 1};
        c.sendCommand(cmd, std::chrono::seconds(10));
    }
    c.receiveFrame(std::chrono::seconds(5));  // the first one, whatever its size
    const ClientStats s0 = c.stats();
    std::size_t particles = 0;
    const auto t0 = Clock::now();
    while (seconds(Clock::now() - t0) < secs)
        if (auto f = c.receiveFrame(std::chrono::milliseconds(100))) {
            particles = f->count();
            c.recycle(std::move(*f));  // as a viewer would: the next frame reuses its memory
        }
    const double dt = seconds(Clock::now() - t0);
    const ClientStats s1 = c.stats();
    const double fps = double(s1.framesReceived - s0.framesReceived) / dt;
    const double mb = double(s1.bytesReceived - s0.bytesReceived) / dt / 1e6;
    std::printf("frames_per_s %.1f mb_per_s %.1f particles %zu bytes_per_particle %.2f lost %llu\n", fps, mb, particles,
                particles && fps > 0 ? mb * 1e6 / fps / double(particles) : 0.0,
                (unsigned long long)(s1.framesLost - s0.framesLost));
    return 0;
}

int probe(ClientSession& c, double secs, double hz) {
    Probe p;
    p.active = true;
    p.position = 0.5 * (c.scene().boxLo + c.scene().boxHi);
    p.k1 = 0.5;
    std::map<std::uint64_t, Clock::time_point> sent;
    std::vector<double> rtt;
    std::uint64_t answered = 0;
    const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / hz));
    auto next = Clock::now();
    const auto end = next + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(secs));
    for (std::uint64_t seq = 1; Clock::now() < end; ++seq) {
        p.seq = seq;
        sent[seq] = Clock::now();
        c.sendProbe(p);
        next += period;
        while (Clock::now() < next) {
            // Only our own probes count: feedback names the probe last applied, which right after
            // connecting may be an earlier client's (sequences are per client).
            if (auto fb = c.waitFeedback(next); fb && fb->probeSeq > answered && sent.count(fb->probeSeq)) {
                const auto now = Clock::now();
                for (auto it = sent.begin(); it != sent.end() && it->first <= fb->probeSeq;) {
                    if (it->first == fb->probeSeq) rtt.push_back(seconds(now - it->second) * 1e3);
                    it = sent.erase(it);
                }
                answered = fb->probeSeq;
            }
        }
    }
    const double first = rtt.empty() ? 0.0 : rtt.front();
    std::printf("probes %zu answered_rtt %zu rtt_ms_p50 %.3f rtt_ms_p99 %.3f rtt_ms_max %.3f rtt_ms_first %.3f\n",
                std::size_t(answered), rtt.size(), percentile(rtt, 0.5), percentile(rtt, 0.99), percentile(rtt, 1.0),
                first);
    return 0;
}

int rate(ClientSession& c, double secs) {
    std::vector<double> r;
    const auto t0 = Clock::now();
    while (seconds(Clock::now() - t0) < secs)
        if (auto f = c.receiveFrame(std::chrono::milliseconds(100));
            f && f->stats.stepRateHz > 0 && seconds(Clock::now() - t0) > 1)
            r.push_back(f->stats.stepRateHz);
    std::printf("steps_per_s %.1f samples %zu\n", percentile(r, 0.5), r.size());
    return 0;
}

int stuck(ClientSession& c, double secs) {
    zmq::context_t ctx;
    zmq::socket_t s(ctx, zmq::socket_type::sub);
    s.set(zmq::sockopt::linger, 0);
    s.set(zmq::sockopt::rcvhwm, 1);
    s.connect(c.frameEndpoint());
    s.set(zmq::sockopt::subscribe, "");
    std::this_thread::sleep_for(std::chrono::duration<double>(secs));
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    return bop::runTool("bop-stream-bench", [&] {
        CLI::App app{"bop-stream-bench: a client's view of a served run (frames/s, MB/s, probe round trip, step rate)"};
        std::string mode, endpoint;
        double secs = 5, hz = 1000;
        bool pause = false;
        app.add_option("mode", mode, "frames, probe, rate or stuck")
            ->required()
            ->check(CLI::IsMember({"frames", "probe", "rate", "stuck"}));
        app.add_option("endpoint", endpoint, "the server's control endpoint, tcp://HOST:PORT")->required();
        app.add_option("--seconds", secs, "how long to measure, s")->check(CLI::PositiveNumber);
        app.add_option("--hz", hz, "probe rate, Hz")->check(CLI::Range(1.0, 10000.0));
        app.add_flag("--pause", pause, "pause the server first (frames: the stream alone)");
        bool udp = false;
        app.add_flag("--udp", udp, "probe: probes and feedback as datagrams instead of over ZeroMQ");
        CLI11_PARSE(app, argc, argv);
        ClientOptions o;
        o.probeOverUdp = udp;
        o.role = mode == "probe" ? Role::Haptic : Role::Viewer;
        o.clientName = "bop-stream-bench";
        ClientSession c(o);
        c.connect(endpoint, std::chrono::seconds(30));
        if (mode == "frames") return frames(c, secs, pause);
        if (mode == "probe") return probe(c, secs, hz);
        if (mode == "rate") return rate(c, secs);
        return stuck(c, secs);
    });
}
