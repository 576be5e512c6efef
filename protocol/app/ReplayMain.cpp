// bop-replay: a recorded session (bop-server --record) played back.
//   serve FILE    acts as the server: answers handshakes with the recorded scene and publishes the
//                 recorded frames at the recorded pace (or --speed times faster)
//   check FILE    runs a fresh bop-server on the recorded inputs (same scene, same rank count)
//                 and compares its frames with the recorded ones, step by step, bit for bit
//   compare A B   only the comparison, of two recordings
//   export IN OUT IN rewritten chunked, indexed and zstd-compressed, with the Foxglove channels
//                 (recording/RecordingExport.hpp), for recordings made without them
#include "bop/common/Error.hpp"
#include "bop/common/ToolMain.hpp"
#include "recording/RecordingExport.hpp"
#include "recording/SessionReader.hpp"
#include "server/ServerFront.hpp"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <map>
#include <thread>

#include <sys/wait.h>
#include <unistd.h>

using namespace bop;
using namespace bop::protocol;

namespace {

using Clock = std::chrono::steady_clock;

template <class T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// Frames by (step, chunk index): the first frame sent at each step.
std::map<std::pair<std::uint64_t, std::uint32_t>, const StateFrame*> byStep(const RecordedSession& s) {
    std::map<std::pair<std::uint64_t, std::uint32_t>, const StateFrame*> out;
    std::map<std::uint64_t, std::uint64_t> seqOfStep;
    for (const auto& c : s.chunks) {
        const auto [it, fresh] = seqOfStep.emplace(c.frame.step, c.frame.frameSeq);
        if (it->second == c.frame.frameSeq) out.emplace(std::make_pair(c.frame.step, c.frame.chunkIndex), &c.frame);
    }
    return out;
}

int compare(const std::string& a, const std::string& b) {
    const RecordedSession ra = readSession(a), rb = readSession(b);
    const auto fa = byStep(ra), fb = byStep(rb);
    std::size_t same = 0, missing = 0, differ = 0;
    for (const auto& [key, f] : fa) {
        const auto it = fb.find(key);
        if (it == fb.end()) {
            ++missing;
            continue;
        }
        const StateFrame& g = *it->second;
        const bool ok = sameBits(f->positions, g.positions) && sameBits(f->normals, g.normals) &&
                        sameBits(f->species, g.species) && sameBits(f->ids, g.ids) && f->probeForce == g.probeForce;
        if (ok) {
            ++same;
        } else if (differ++ == 0) {
            std::cout << "first difference: step " << key.first << ", chunk " << key.second << " (" << f->count()
                      << " vs " << g.count() << " particles)\n";
        }
    }
    std::cout << same << " of " << fa.size() << " frame chunks identical bit for bit, " << differ << " differ, "
              << missing << " missing from " << b << "\n";
    return same == fa.size() && !fa.empty() ? 0 : 1;
}

int runProcess(const std::vector<std::string>& args) {
    std::cout << "running:";
    for (const auto& a : args) std::cout << " " << a;
    std::cout << std::endl;
    const pid_t pid = fork();
    if (pid < 0) throw Error("bop-replay", std::string("fork: ") + std::strerror(errno));
    if (pid == 0) {
        std::vector<char*> argv;
        for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        execvp(argv[0], argv.data());
        std::cerr << "bop-replay: cannot run " << args[0] << ": " << std::strerror(errno) << "\n";
        _exit(127);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

int check(const std::string& file, std::string server, int ranks, const std::string& outDir) {
    const RecordedSession s = readSession(file);
    const auto meta = [&](const std::string& k) {
        const auto it = s.meta.find(k);
        return it == s.meta.end() ? std::string() : it->second;
    };
    if (meta("scene").empty()) throw Error(file, "the recording does not name its scene file");
    if (ranks <= 0) ranks = meta("ranks").empty() ? 1 : std::stoi(meta("ranks"));
    if (server.empty()) {
        const auto here = std::filesystem::read_symlink("/proc/self/exe").parent_path();
        server = (here.parent_path() / "dynamics_server" / "bop-server").string();
    }
    std::filesystem::create_directories(outDir);
    const std::string replayed = outDir + "/replayed.mcap";
    std::vector<std::string> args;
    if (ranks > 1) args = {"mpirun", "-np", std::to_string(ranks), "--oversubscribe"};
    for (const std::string& a :
         {server, meta("scene"), std::string("--port"), std::string("0"), std::string("--replay-inputs"), file,
          std::string("--record"), replayed, std::string("-o"), outDir})
        args.push_back(a);
    if (!meta("restart").empty()) args.insert(args.end(), {"--restart", meta("restart")});
    if (!meta("precision").empty()) args.insert(args.end(), {"--precision", meta("precision")});
    if (const int rc = runProcess(args); rc != 0)
        throw Error(server, "the replaying server exited with " + std::to_string(rc));
    return compare(file, replayed);
}

int serve(const std::string& file, FrontOptions front, double speed, bool wait) {
    const RecordedSession s = readSession(file);
    front.udp = false;
    ServerFront f(front, s.scene);
    std::cout << "listening on " << f.controlEndpoint() << " (frames on port " << f.framePort() << ")" << std::endl;
    if (wait)
        while (!f.waitForClient(std::chrono::milliseconds(200))) {
        }
    std::map<std::uint64_t, std::vector<const RecordedChunk*>> frames;  // by frame sequence, in order
    for (const auto& c : s.chunks) frames[c.frame.frameSeq].push_back(&c);
    const auto t0 = Clock::now();
    const std::uint64_t first = s.chunks.empty() ? 0 : s.chunks.front().logTimeNs;
    std::size_t sent = 0;
    for (const auto& [seq, chunks] : frames) {
        const double at = double(chunks.front()->logTimeNs - first) * 1e-9 / speed;
        std::this_thread::sleep_until(t0 +
                                      std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(at)));
        std::vector<Buffer> bytes;
        for (const auto* c : chunks) bytes.push_back(c->bytes);
        f.offerEncodedFrame(std::move(bytes));
        ++sent;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // the last frame leaves
    f.finish();
    std::cout << "served " << sent << " recorded frames\n";
    return 0;
}

int exportFile(const std::string& in, const std::string& out, const recording::McapWriterOptions& options) {
    const ExportReport r = exportRecording(in, out, options);
    const double perSecond = r.seconds > 0 ? 1 / r.seconds : 0;
    std::cout << out << ": " << r.messagesCopied << " messages copied, " << r.framesDerived
              << " frames for Foxglove (point cloud, surfels, probe, transform, stats), " << r.chunks << " chunks\n"
              << "  " << r.inputBytes << " bytes in (" << std::lround(double(r.inputBytes) * perSecond)
              << " per recorded second), " << r.outputBytes << " bytes out ("
              << std::lround(double(r.outputBytes) * perSecond) << " per recorded second) over " << r.seconds << " s\n";
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    return runTool("bop-replay", [&] {
        CLI::App app{"bop-replay: play back a session recorded with bop-server --record (MCAP)"};
        app.require_subcommand(1);
        std::string file, other, server, outDir = "out/replay";
        int ranks = 0;
        double speed = 1;
        bool wait = false;
        FrontOptions front;
        auto* s = app.add_subcommand("serve", "act as the server: the recorded scene and frames, at the recorded pace");
        s->add_option("file", file, "recording (.mcap)")->required();
        s->add_option("--port", front.basePort, "base port (0 = ephemeral)");
        s->add_option("--bind", front.bindAddress, "address to bind");
        s->add_option("--speed", speed, "playback speed, times the recorded pace")->check(CLI::PositiveNumber);
        s->add_flag("--wait-for-client", wait, "start playing when the first client has said hello");
        auto* c = app.add_subcommand("check", "run a fresh server on the recorded inputs and compare its frames");
        c->add_option("file", file, "recording (.mcap)")->required();
        c->add_option("--server", server, "bop-server executable (default: next to this tool's build folder)");
        c->add_option("--np", ranks, "ranks (default: as recorded)");
        c->add_option("-o,--out", outDir, "folder for the replayed recording");
        auto* k = app.add_subcommand("compare", "compare the frames of two recordings, step by step");
        k->add_option("recorded", file, "recording (.mcap)")->required();
        k->add_option("replayed", other, "recording (.mcap)")->required();
        recording::McapWriterOptions mcap;
        auto* x = app.add_subcommand("export",
                                     "rewrite a recording for Foxglove: chunked, indexed, zstd, 3D and plot channels");
        x->add_option("file", file, "recording (.mcap, or an unfinished .mcap.partial)")->required();
        x->add_option("out", other, "the new recording (.mcap)")->required();
        x->add_option("--zstd-level", mcap.zstdLevel, "zstd level, 1 (fast) .. 19 (small)")->check(CLI::Range(1, 19));
        bool plain = false;
        x->add_flag("--no-compression", plain, "chunks stored uncompressed");
        x->add_option("--chunk-kib", mcap.chunkBytes, "uncompressed KiB a chunk collects (0: no chunks, no index)")
            ->check(CLI::Range(0, 1 << 18))
            ->transform([](std::string v) { return std::to_string(std::stoull(v) * 1024); });
        try {
            app.parse(argc, argv);
        } catch (const CLI::ParseError& e) {
            return app.exit(e);
        }
        if (s->parsed()) return serve(file, front, speed, wait);
        if (c->parsed()) return check(file, server, ranks, outDir);
        if (plain) mcap.compression = recording::McapCompression::None;
        if (x->parsed()) return exportFile(file, other, mcap);
        return compare(file, other);
    });
}
