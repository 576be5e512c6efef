// Writes seed corpora for the fuzz targets (FuzzDecoders.cpp): a few valid buffers per target,
// made with the protocol's own encoders and McapWriter, so no binary seeds live in git.
//   bop_fuzz_seeds OUTDIR   ->  OUTDIR/<target>/<name>.bin (targets: hello scene frame probe
//                               feedback command reply maprequest mapchunk refusal mcap front);
//                               existing files are overwritten.
// Exits non-zero if a sample cannot be encoded or written.
#include "ProtocolSamples.hpp"
#include "codec/Codec.hpp"
#include "igtl/IgtlWire.hpp"
#include "recording/McapWriter.hpp"

#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace bop::protocol;
using namespace bop::protocol::samples;

fs::path gOut;
int gCount = 0;

void put(const std::string& target, const std::string& name, const std::vector<std::uint8_t>& bytes) {
    const fs::path dir = gOut / target;
    fs::create_directories(dir);
    const fs::path file = dir / (name + ".bin");
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    if (!out.flush()) throw std::runtime_error("cannot write " + file.string());
    ++gCount;
}

std::vector<std::uint8_t> readAll(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

void handshake() {
    put("hello", "sample", encodeHello(sampleHello()));
    put("hello", "default", encodeHello(Hello{}));
    Hello h = sampleHello();
    h.role = Role::Control;
    h.readOnly = false;
    h.clientName = std::string(kMaxNameBytes, 'n');
    h.udpFramePort = 0;
    put("hello", "control-longname", encodeHello(h));

    put("scene", "sample4", encodeSceneInfo(sampleScene(4)));
    put("scene", "sample1", encodeSceneInfo(sampleScene(1)));
    SceneInfo s = sampleScene(12);
    s.gridDims = {0, 0, 0};
    s.r0Voxels = 0;
    s.publishRateHz = 0;
    s.endpoints = {"ipc:///tmp/bop-frames", 0, 0};
    put("scene", "sample12-nomap", encodeSceneInfo(s));
}

void haptics() {
    put("probe", "sample", encodeProbe(sampleProbe()));
    put("probe", "default", encodeProbe(Probe{}));
    put("feedback", "sample", encodeFeedback(sampleFeedback()));
    put("feedback", "default", encodeFeedback(Feedback{}));
    put("maprequest", "sample", encodeMapRequest(sampleMapRequest()));
    put("maprequest", "one", encodeMapRequest({0, 1}));
    put("mapchunk", "sample", encodeMapChunk(sampleMapChunk()));
    put("mapchunk", "nomap", encodeMapChunk(MapChunk{}));
    put("mapedits", "sample", encodeMapEdits(sampleMapEdits()));
    put("mapedits", "none", encodeMapEdits(MapEdits{}));
    put("refusal", "sample", encodeRefusal(sampleRefusal()));
    {  // OpenIGTLink: a tool's transform then a status message; a transform with protocol 3's extended header
        Eigen::Matrix4d t = Eigen::Matrix4d::Identity();
        t(0, 3) = 10, t(1, 3) = -20, t(2, 3) = 30;
        const std::vector<std::uint8_t> body = bop::igtl::transformBody(t);
        std::vector<std::uint8_t> stream = bop::igtl::encodeMessage("TRANSFORM", "StylusTipToReference", body);
        const std::vector<std::uint8_t> status =
            bop::igtl::encodeMessage("STATUS", "Tool", std::vector<std::uint8_t>(30, 0));
        stream.insert(stream.end(), status.begin(), status.end());
        put("igtl", "transform-status", stream);
        std::vector<std::uint8_t> v3 = {0, 12, 0, 2, 0, 0, 0, 3, 0, 0, 0, 7};
        v3.insert(v3.end(), body.begin(), body.end());
        for (const char b : {'\0', '\1', 'a', 'b', 'c'}) v3.push_back(std::uint8_t(b));
        put("igtl", "transform-v3", bop::igtl::encodeMessage("TRANSFORM", "Tool", v3, 2));
    }
    put("refusal", "empty", encodeRefusal(Refusal{}));
}

void commands() {
    static const char* const names[] = {"seed", "birth", "parameter", "run", "mapframe", "checkpoint", "record"};
    const std::vector<Command> cmds = sampleCommands();
    for (std::size_t i = 0; i < cmds.size(); ++i)
        put("command", std::string(i < std::size(names) ? names[i] : "command") + std::to_string(i),
            encodeCommand(cmds[i]));

    put("reply", "sample", encodeCommandReply(sampleReply()));
    for (int st = 0; st <= int(ReplyStatus::Failed); ++st)
        put("reply", "status" + std::to_string(st),
            encodeCommandReply({std::uint64_t(100 + st), ReplyStatus(st), std::uint64_t(st) * 10, "status text"}));
}

void frames() {
    put("frame", "f32-5-normals-ids", encodeStateFrame(sampleFrame(5, FrameEncoding::Float32, true, true)));
    put("frame", "q16-5-normals", encodeStateFrame(sampleFrame(5, FrameEncoding::Quantised16, true, false)));
    put("frame", "f32-0", encodeStateFrame(sampleFrame(0, FrameEncoding::Float32, false, false)));
    put("frame", "f32-64-plain", encodeStateFrame(sampleFrame(64, FrameEncoding::Float32, false, false, 11)));
    put("frame", "q16-64-ids", encodeStateFrame(sampleFrame(64, FrameEncoding::Quantised16, false, true, 12)));
    put("frame", "c8-64-normals-ids", encodeStateFrame(sampleFrame(64, FrameEncoding::Compact8, true, true, 14)));
    // A frame split into chunks: the first, a middle and the last chunk (nonzero chunk index and
    // first index), each well below the 1 MiB -max_len of the frame target.
    const std::vector<Buffer> chunks =
        encodeStateFrameChunks(sampleFrame(3000, FrameEncoding::Quantised16, true, true, 13), 16 * 1024);
    if (chunks.size() < 3) throw std::runtime_error("expected at least 3 chunks, got " + std::to_string(chunks.size()));
    put("frame", "chunk-first", chunks.front());
    put("frame", "chunk-middle", chunks[chunks.size() / 2]);
    put("frame", "chunk-last", chunks.back());
}

// MCAP files as McapWriter writes them: complete, empty, unfinished (PATH.partial) and cut short.
void mcap() {
    using bop::recording::McapWriter;
    const fs::path dir = gOut / "mcap";
    fs::create_directories(dir);
    const fs::path scratch = gOut / ".mcap-scratch";
    fs::create_directories(scratch);

    const auto writeSession = [&](const fs::path& path, bool close) {
        McapWriter w(path.string(), "");
        const std::vector<std::uint8_t> schemaBytes = {0x10, 0, 0, 0, 'B', 'F', 'B', 'S', 1, 2, 3, 4};
        const auto scene = w.addSchema("bop.wire.SceneInfo", "flatbuffer", schemaBytes);
        const auto probe = w.addSchema("bop.wire.Probe", "flatbuffer", schemaBytes);
        const auto sceneCh = w.addChannel(scene, "/bop/scene", "flatbuffer", {{"scene", "bag.toml"}, {"ranks", "2"}});
        const auto probeCh = w.addChannel(probe, "/bop/probe", "flatbuffer");
        const auto rawCh = w.addChannel(0, "/bop/raw", "");
        w.write(sceneCh, 0, 1000, 1000, encodeSceneInfo(sampleScene(2)));
        for (std::uint32_t i = 0; i < 3; ++i) {
            Probe p = sampleProbe();
            p.seq = i;
            w.write(probeCh, i, 2000 + i, 1990 + i, encodeProbe(p));
        }
        w.write(rawCh, 0, 3000, 3000, std::vector<std::uint8_t>{});
        if (close) {
            w.close();
        } else {
            w.flush();
        }
    };

    writeSession(scratch / "session.mcap", true);
    const std::vector<std::uint8_t> full = readAll(scratch / "session.mcap");
    put("mcap", "session", full);
    put("mcap", "session-cut-half", std::vector<std::uint8_t>(full.begin(), full.begin() + full.size() / 2));
    put("mcap", "session-cut-footer", std::vector<std::uint8_t>(full.begin(), full.end() - 12));

    writeSession(scratch / "unfinished.mcap", false);  // the destructor leaves PATH.partial
    put("mcap", "unfinished-partial", readAll(scratch / "unfinished.mcap.partial"));

    {
        McapWriter w((scratch / "empty.mcap").string(), "bop");
        w.close();
    }
    put("mcap", "empty", readAll(scratch / "empty.mcap"));
    fs::remove_all(scratch);
}

}  // namespace

// Sequences for the front target (FuzzFront.cpp): [op][length][message] records and passes.
class Sequence {
public:
    Sequence& from(int peer, const Buffer& m) {
        bytes_.push_back(std::uint8_t(4 * peer));  // op % 4 == 0: a message
        bytes_.push_back(std::uint8_t(m.size() & 0xff));
        bytes_.push_back(std::uint8_t(m.size() >> 8));
        bytes_.insert(bytes_.end(), m.begin(), m.end());
        return *this;
    }
    Sequence& passes(int n) {  // 1..8
        bytes_.push_back(std::uint8_t(2 + 4 * (n - 1)));
        return *this;
    }
    const std::vector<std::uint8_t>& bytes() const { return bytes_; }

private:
    std::vector<std::uint8_t> bytes_;
};

Command command(std::uint64_t id, CommandBody body) {
    return {id, std::move(body)};
}

void front() {
    const Buffer hello = encodeHello({});
    Probe p;
    p.active = true;
    p.position = {10, 10, 10};  // the ball's centre, about
    p.k1 = 5;
    Sequence poke;
    Command resume{1, RunControl{RunAction::Resume, 1}};  // each input starts paused (FuzzFront.cpp)
    poke.from(0, hello).from(0, encodeCommand(resume)).passes(1);
    for (int k = 1; k <= 8; ++k) {
        p.seq = std::uint64_t(k);
        p.position.x() += 0.5;
        poke.from(0, encodeProbe(p)).passes(2);
    }
    put("front", "poke", poke.bytes());
    Sequence tune;
    tune.from(1, hello)
        .from(1, encodeCommand(command(1, SetParameter{"lj", 1, 2, 2.5})))
        .from(1, encodeCommand(command(2, SetParameter{"co_planar", 1, 1, 0.1})))
        .from(1, encodeCommand(command(3, SetParameter{"drag_v", 2, 0, 0.2})))
        .from(1, encodeCommand(command(4, SetParameter{"k0", 0, 0, 2})))
        .passes(4)
        .from(1, encodeCommand(command(5, RunControl{RunAction::Pause, 1})))
        .from(1, encodeCommand(command(6, RunControl{RunAction::SingleStep, 3})))
        .passes(8)
        .from(1, encodeCommand(command(7, RunControl{RunAction::Resume, 1})))
        .passes(2);
    put("front", "tune", tune.bytes());
    Sequence build;
    build.from(2, hello)
        .from(2, encodeCommand(command(9, RunControl{RunAction::Resume, 1})))
        .from(2, encodeCommand(command(1, SeedParticle{2, {10, 10, 10}})))
        .from(2, encodeCommand(command(2, SetBirth{2, true})))
        .from(2, encodeCommand(command(3, Record{true, "fuzz.mcap"})))
        .passes(8)
        .from(3, hello)
        .from(3, encodeMapRequest({0, 4096}))
        .from(3, encodeMapRequest({4096, 4096}))
        .from(3, encodeMapEditsRequest({0}))
        .passes(1);
    put("front", "build", build.bytes());
}

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s OUTDIR\n", argv[0]);
        return 2;
    }
    try {
        gOut = argv[1];
        handshake();
        haptics();
        commands();
        frames();
        mcap();
        front();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bop_fuzz_seeds: %s\n", e.what());
        return 1;
    }
    std::printf("bop_fuzz_seeds: %d seeds in %s\n", gCount, gOut.string().c_str());
    return 0;
}
