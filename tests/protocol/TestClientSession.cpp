// The client session against a fake server in the test (client/ClientSession.hpp): a ROUTER that
// answers Hello, commands and probes, and a PUB that the test drives with chunked frames and
// tier topics (docs/protocol.md). Ports are ephemeral; CURVE both with the right and a wrong key.
#include "ProtocolSamples.hpp"
#include "bop/common/Error.hpp"
#include "client/ClientSession.hpp"
#include "codec/Codec.hpp"
#include "security/CurveKeys.hpp"

#include <catch2/catch.hpp>
#include <zmq.hpp>

#include <algorithm>
#include <atomic>
#include <bit>
#include <set>
#include <thread>

using namespace bop::protocol;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

namespace {

constexpr std::size_t kParticles = 20;
constexpr std::size_t kChunkBytes = 1024 + 10 * 33;  // 10 Float32 particles with normals and ids: 2 chunks

StateFrame frameWith(std::uint64_t seq) {
    StateFrame f = samples::sampleFrame(kParticles, FrameEncoding::Float32, true, true, std::uint32_t(seq));
    f.frameSeq = seq;
    f.step = 100 * seq;
    return f;
}

// Frame `seq` as the client should hand it out: one chunk, values as decoded.
StateFrame expectedFrame(std::uint64_t seq) {
    const Buffer b = encodeStateFrame(frameWith(seq));
    return decodeStateFrame(b.data(), b.size()).value;
}

class FakeServer {
public:
    explicit FakeServer(const std::string& curveSecretKey = "", float publishHz = 60) : publishHz_(publishHz) {
        for (zmq::socket_t* s : {&router_, &pub_}) {
            s->set(zmq::sockopt::linger, 0);
            if (!curveSecretKey.empty()) {
                s->set(zmq::sockopt::curve_server, 1);
                s->set(zmq::sockopt::curve_secretkey, curveSecretKey);
            }
            s->bind("tcp://127.0.0.1:*");  // ephemeral port, read back below
        }
        control = router_.get(zmq::sockopt::last_endpoint);
        frames = pub_.get(zmq::sockopt::last_endpoint);
        thread_ = std::thread([this] { loop(); });
    }
    ~FakeServer() {
        stop_ = true;
        thread_.join();
    }

    // Publishes frame `seq` (counted from 1) in chunks, each [tier, chunk]. Test thread only.
    std::size_t publish(std::uint64_t seq) {
        const std::uint8_t tier = std::uint8_t(std::min(std::countr_zero(seq), 7));
        const std::vector<Buffer> chunks = encodeStateFrameChunks(frameWith(seq), kChunkBytes);
        for (const Buffer& c : chunks) publishRaw(tier, c);
        return chunks.size();
    }
    void publishRaw(std::uint8_t tier, const Buffer& body) {
        pub_.send(zmq::buffer(&tier, 1), zmq::send_flags::sndmore);
        pub_.send(zmq::buffer(body));
    }

    std::string control, frames;
    std::atomic<int> hellos{0};

private:
    void send(const zmq::message_t& id, const Buffer& b) {
        router_.send(zmq::buffer(id.data(), id.size()), zmq::send_flags::sndmore);
        router_.send(zmq::buffer(b));
    }
    void loop() {
        zmq::pollitem_t item{router_.handle(), 0, ZMQ_POLLIN, 0};
        while (!stop_) {
            if (zmq::poll(&item, 1, 10ms) == 0) continue;
            zmq::message_t id, body;
            if (!router_.recv(id) || !router_.recv(body)) continue;
            const auto* data = static_cast<const std::uint8_t*>(body.data());
            switch (messageKind(data, body.size())) {
                case MessageKind::Hello: {
                    ++hellos;
                    send(id, Buffer{'j', 'u', 'n', 'k', 0, 0, 0, 0, 0, 0});  // the client counts and skips it
                    SceneInfo s = samples::sampleScene();
                    s.endpoints.frameEndpoint = frames;
                    s.publishRateHz = publishHz_;
                    send(id, encodeSceneInfo(s));
                    break;
                }
                case MessageKind::Command: {
                    const Command c = decodeCommand(data, body.size()).value;
                    send(id, encodeFeedback(Feedback{3, 42, {1, 2, 3}, 99}));  // arrives before the reply
                    send(id, encodeCommandReply(CommandReply{c.requestId + 1000, ReplyStatus::Ok, 1, "not yours"}));
                    send(id, encodeCommandReply(CommandReply{c.requestId, ReplyStatus::Ok, 42, "done"}));
                    break;
                }
                case MessageKind::Probe:
                    send(id, encodeFeedback(Feedback{decodeProbe(data, body.size()).value.seq, 43, {0, 1, 0}, 100}));
                    break;
                default:
                    break;
            }
        }
    }

    float publishHz_;
    zmq::context_t ctx_{1};
    zmq::socket_t router_{ctx_, zmq::socket_type::router}, pub_{ctx_, zmq::socket_type::pub};
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

// Publishes frames 1, 2, ... until `got` says the client has what it needs (the SUB socket's
// subscription reaches the PUB socket some time after connect); false after 5 s.
template <class Got>
bool publishUntil(FakeServer& server, Got got) {
    const auto deadline = Clock::now() + 5s;
    for (std::uint64_t seq = 1; Clock::now() < deadline; ++seq) {
        server.publish(seq);
        if (got(seq)) return true;
    }
    return false;
}

ClientOptions optionsWith(float frameRateHz, const std::string& serverKey = "") {
    ClientOptions o;
    o.clientName = "test-client";
    o.frameRateHz = frameRateHz;
    o.curveServerKey = serverKey;
    return o;
}

}  // namespace

TEST_CASE("ClientSession: handshake, command reply, feedback and a reassembled frame", "[protocol][client]") {
    FakeServer server;
    ClientSession client(optionsWith(0));
    const SceneInfo scene = client.connect(server.control, 3000ms);
    SceneInfo expected = samples::sampleScene();
    expected.endpoints.frameEndpoint = server.frames;
    expected.publishRateHz = 60;
    CHECK(samples::same(scene, expected));
    CHECK(client.frameEndpoint() == server.frames);
    CHECK(client.frameTier() == 0);
    CHECK(client.stats().malformed == 1);  // the junk before SceneInfo

    const CommandReply reply = client.sendCommand(Command{77, RunControl{RunAction::Pause, 1}}, 3000ms);
    CHECK(reply.requestId == 77);
    CHECK(reply.step == 42);
    CHECK(reply.message == "done");
    CHECK(client.stats().repliesDropped == 1);
    const auto feedback = client.pollFeedback();
    REQUIRE(feedback.has_value());
    CHECK(feedback->step == 42);
    CHECK_FALSE(client.pollFeedback().has_value());

    Probe probe;
    probe.seq = 9;
    REQUIRE(client.sendProbe(probe));
    std::optional<Feedback> echoed;
    for (const auto deadline = Clock::now() + 3s; !echoed && Clock::now() < deadline; std::this_thread::sleep_for(5ms))
        echoed = client.pollFeedback();
    REQUIRE(echoed.has_value());
    CHECK(echoed->probeSeq == 9);
    // waitFeedback returns the echo when it comes; with nothing coming, at the deadline, not before.
    probe.seq = 10;
    REQUIRE(client.sendProbe(probe));
    const auto waited = client.waitFeedback(Clock::now() + 3s);
    REQUIRE(waited.has_value());
    CHECK(waited->probeSeq == 10);
    const auto t0 = Clock::now();
    CHECK_FALSE(client.waitFeedback(t0 + 30ms).has_value());
    CHECK(Clock::now() - t0 >= 30ms);

    std::optional<StateFrame> frame;
    REQUIRE(publishUntil(server, [&](std::uint64_t) { return (frame = client.receiveFrame(20ms)).has_value(); }));
    CHECK(samples::same(*frame, expectedFrame(frame->frameSeq)));
    // A frame message that is not a frame is counted, and the next frame still arrives.
    server.publishRaw(0, Buffer(64, 0xAB));
    const std::uint64_t next = frame->frameSeq + 100;
    server.publish(next);
    frame = client.receiveFrame(3000ms);
    REQUIRE(frame.has_value());
    CHECK(samples::same(*frame, expectedFrame(next)));
    const ClientStats stats = client.stats();
    CHECK(stats.malformed == 2);
    CHECK(stats.framesReceived >= 2);
    CHECK(stats.chunksReceived >= 4);
    CHECK(stats.bytesReceived > 2 * kParticles * 33);  // two frames' particles at least
}

TEST_CASE("ClientSession: half the rate gets even frames only; the receiver thread keeps the newest",
          "[protocol][client]") {
    FakeServer server;
    ClientSession half(optionsWith(30)), full(optionsWith(0));
    half.connect(server.control, 3000ms);
    full.connect(server.control, 3000ms);
    CHECK(half.frameTier() == 1);
    full.startReceiver();
    CHECK(full.receiving());
    CHECK_THROWS_AS(full.receiveFrame(1ms), std::logic_error);

    std::set<std::uint64_t> halfSeqs, fullSeqs;
    const bool enough = publishUntil(server, [&](std::uint64_t) {
        if (auto f = half.receiveFrame(5ms)) halfSeqs.insert(f->frameSeq);
        const LatestFrame latest = full.latestFrame();
        if (latest.frame) fullSeqs.insert(latest.frame->frameSeq);
        const bool odd = std::any_of(fullSeqs.begin(), fullSeqs.end(), [](std::uint64_t s) { return s % 2 == 1; });
        return halfSeqs.size() >= 3 && odd;
    });
    REQUIRE(enough);
    for (const std::uint64_t s : halfSeqs) CHECK(s % 2 == 0);

    const LatestFrame latest = full.latestFrame();
    REQUIRE(latest.frame);
    CHECK(latest.count >= fullSeqs.size());
    CHECK(samples::same(*latest.frame, expectedFrame(latest.frame->frameSeq)));
    full.stopReceiver();
    CHECK_FALSE(full.receiving());
    CHECK(full.receiverError().empty());
    CHECK(full.stats().malformed == 1);  // only the junk before SceneInfo
}

TEST_CASE("ClientSession: CURVE with the server's key works, a wrong key gets no answer", "[protocol][client]") {
    REQUIRE(zmq_has("curve") == 1);
    const CurveKeyPair serverKeys = makeCurveKeyPair();
    FakeServer server(serverKeys.secretKey);

    ClientSession good(optionsWith(0, serverKeys.publicKey));
    good.connect(server.control, 3000ms);
    CHECK(server.hellos == 1);
    REQUIRE(publishUntil(server, [&](std::uint64_t) { return good.receiveFrame(20ms).has_value(); }));

    ClientSession wrong(optionsWith(0, makeCurveKeyPair().publicKey));
    try {
        wrong.connect(server.control, 300ms);
        FAIL("connected with a wrong server key");
    } catch (const bop::Error& e) {
        CHECK(e.where() == server.control);
        CHECK_THAT(e.what(), Catch::Contains("no SceneInfo within 300 ms"));
    }
    ClientSession plain(optionsWith(0));
    CHECK_THROWS_AS(plain.connect(server.control, 300ms), bop::Error);
    CHECK(server.hellos == 1);
    CHECK_FALSE(wrong.connected());

    ClientOptions badKey = optionsWith(0, "not a key");
    CHECK_THROWS_WITH(ClientSession(badKey).connect(server.control, 300ms), Catch::Contains("CURVE server key"));
}

TEST_CASE("ClientSession: no server, and tiers for rates", "[protocol][client]") {
    ClientSession client(optionsWith(0));
    CHECK_THROWS_WITH(client.connect("tcp://127.0.0.1:1", 100ms),
                      Catch::Contains("tcp://127.0.0.1:1: no SceneInfo within 100 ms"));
    CHECK_THROWS_WITH(client.connect("nonsense://x", 100ms), Catch::Contains("nonsense://x: cannot connect"));
    CHECK_FALSE(client.connected());
    CHECK_THROWS_AS(client.receiveFrame(1ms), std::logic_error);

    CHECK(frameTierFor(60, 0) == 0);
    CHECK(frameTierFor(60, 60) == 0);
    CHECK(frameTierFor(60, 120) == 0);
    CHECK(frameTierFor(60, 30) == 1);
    CHECK(frameTierFor(60, 20) == 1);
    CHECK(frameTierFor(60, 15) == 2);
    CHECK(frameTierFor(240, 1) == 7);
    CHECK(frameTierFor(0, 30) == 0);
}
