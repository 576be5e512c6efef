// The server's network front in this process (server/ServerFront.hpp), reached over loopback by
// hand-made messages: every number a client sends is refused just outside its valid range, as
// NaN, as infinity and as a huge finite value, with a reason naming the field, counted and never
// handed to the step loop; the values at the bounds are taken. Exceptions inside the front are
// counted and the front goes on; silent sessions are forgotten. Ports are ephemeral.
#include "HostileMessages.hpp"
#include "ProtocolSamples.hpp"
#include "client/ClientSession.hpp"
#include "codec/Codec.hpp"
#include "codec/MessageKind.hpp"
#include "codec/Ranges.hpp"
#include "server/InboundRanges.hpp"
#include "server/ServerFront.hpp"
#include "transport/UdpSocket.hpp"

#include <catch2/catch.hpp>
#include <zmq.hpp>

#include <cmath>
#include <limits>
#include <thread>

using namespace bop::protocol;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using namespace bop::test::hostile;

namespace {

// A client speaking the protocol by hand over its own DEALER socket.
class RawClient {
public:
    explicit RawClient(const std::string& endpoint) {
        socket_.set(zmq::sockopt::linger, 0);
        socket_.connect(endpoint);
    }
    void send(const Buffer& b) { socket_.send(zmq::buffer(b), zmq::send_flags::none); }
    // The next message of `kind` within `timeout`; others are skipped.
    std::optional<Buffer> next(MessageKind kind, std::chrono::milliseconds timeout = 3000ms) {
        const auto deadline = Clock::now() + timeout;
        while (Clock::now() < deadline) {
            socket_.set(zmq::sockopt::rcvtimeo, 50);
            zmq::message_t m;
            if (!socket_.recv(m)) continue;
            const auto* p = static_cast<const std::uint8_t*>(m.data());
            if (messageKind(p, m.size()) == kind) return Buffer(p, p + m.size());
        }
        return std::nullopt;
    }
    void hello() {
        send(encodeHello({}));
        REQUIRE(next(MessageKind::SceneInfo));
    }
    // Why the front refused `b`: the reason of its Refusal, or the message of a command's
    // Rejected reply; empty when it sent neither.
    std::string refusalOf(const Buffer& b) {
        send(b);
        const bool command = messageKind(b.data(), b.size()) == MessageKind::Command;
        const auto answer = next(command ? MessageKind::CommandReply : MessageKind::Refusal);
        if (!answer) return {};
        if (!command) return decodeRefusal(answer->data(), answer->size()).value.reason;
        const auto r = decodeCommandReply(answer->data(), answer->size()).value;
        return r.status == ReplyStatus::Rejected ? r.message : std::string();
    }

private:
    zmq::context_t ctx_{1};
    zmq::socket_t socket_{ctx_, zmq::socket_type::dealer};
};

// A scene of 2 species in the box [0, 10]^3 with a 1000-byte map.
SceneInfo smallScene() {
    SceneInfo s = samples::sampleScene(2);
    s.boxLo = {0, 0, 0};
    s.boxHi = {10, 10, 10};
    s.mapBytes = 1000;
    return s;
}

FrontOptions ephemeral() {
    FrontOptions o;
    o.basePort = 0;
    return o;
}

}  // namespace

TEST_CASE("front: every number outside its range is refused with its field named, counted and never applied",
          "[protocol][front]") {
    const SceneInfo scene = smallScene();
    ServerFront front(ephemeral(), scene);
    const std::vector<Case> cases = outOfRange(scene);
    for (const Case& c : cases) {
        RawClient client(front.controlEndpoint());  // a session each: refusals are answered a few a second
        client.hello();
        const std::string why = client.refusalOf(c.message);
        INFO(c.what << ": " << why);
        CHECK(why.find(c.field) != std::string::npos);
    }
    std::this_thread::sleep_for(50ms);
    CHECK_FALSE(front.takeProbe());
    CHECK(front.takeCommands().empty());
    const FrontStats s = front.stats();
    CHECK(s.outOfRange == cases.size());
    CHECK(s.refusalsSent == cases.size());
    CHECK(s.probes == 0);
    CHECK(s.internalErrors == 0);
    // Hello itself: a frame rate out of range is refused, and no session made.
    for (const float rate : {-1e-3f, 10000.5f, float(kNaN), float(kInf)}) {
        RawClient client(front.controlEndpoint());
        CHECK(client.refusalOf(helloMessage(rate)).find("frame_rate_hz") != std::string::npos);
    }
    CHECK(front.stats().sessionsOpened == cases.size());
}

TEST_CASE("front: the values at the bounds of every range are taken", "[protocol][front]") {
    using namespace ranges;
    const SceneInfo scene = smallScene();
    ServerFront front(ephemeral(), scene);
    RawClient client(front.controlEndpoint());
    client.hello();
    const Eigen::AlignedBox3d reach = probeReachBox(scene);
    const std::vector<Buffer> probes = {
        probeMessage(reach.min(), kMinProbeK0, kMinProbeK1, 0, 0, Eigen::Vector3d::Zero(), 1),
        probeMessage(reach.max(), kMaxProbeK0, kMaxProbeK1, kMaxLoopRateHz, kMaxPeriodErrorUs,
                     Eigen::Vector3d::Constant(-kMaxRenderedForce), 2)};
    for (const Buffer& p : probes) {
        client.send(p);
        std::optional<Probe> taken;
        for (int k = 0; k < 200 && !taken; ++k) std::this_thread::sleep_for(5ms), taken = front.takeProbe();
        REQUIRE(taken);
        CHECK(taken->seq == decodeProbe(p.data(), p.size()).value.seq);
    }
    const std::vector<Buffer> commands = {seedMessage(2, scene.boxHi),         parameterMessage("lj", kMaxWeight, 2, 2),
                                          parameterMessage("drag_v", 0, 1, 0), parameterMessage("k0", kMaxProbeK0),
                                          parameterMessage("k1", kMaxProbeK1), singleStepMessage(kMaxSingleSteps),
                                          mapRequestMessage(scene.mapBytes, 1)};
    for (const Buffer& c : commands) client.send(c);
    REQUIRE(client.next(MessageKind::MapChunk));  // after the commands on the same socket
    CHECK(front.takeCommands().size() == commands.size() - 1);
    CHECK(front.stats().outOfRange == 0);
}

TEST_CASE("front: a probe datagram out of range is refused by a Refusal datagram, at most one a second",
          "[protocol][front][udp]") {
    ServerFront front(ephemeral(), smallScene());
    UdpSocket socket("127.0.0.1", 0);
    const Endpoint server{"127.0.0.1", std::uint16_t(front.udpProbePort())};
    for (int k = 0; k < 5; ++k) socket.sendTo(server, probeMessage({5, 5, 5}, 1, 1e300));
    std::optional<Refusal> refusal;
    int refusals = 0;
    for (const auto deadline = Clock::now() + 1500ms; Clock::now() < deadline;)
        if (auto d = socket.receive(20)) {
            const auto r = decodeRefusal(d->bytes.data(), d->bytes.size());
            REQUIRE(r.ok());
            refusal = r.value, ++refusals;
        }
    REQUIRE(refusal);
    CHECK(refusals == 1);
    CHECK(refusal->kind == "Probe");
    CHECK(refusal->seq == 9);
    CHECK(refusal->reason.find("Probe.k1") != std::string::npos);
    CHECK(front.stats().outOfRange == 5);
    CHECK_FALSE(front.takeProbe());
}

TEST_CASE("front: a feedback that is not finite and a reply that cannot be encoded are counted, and the front goes on",
          "[protocol][front]") {
    ServerFront front(ephemeral(), smallScene());
    ClientSession client;
    client.connect(front.controlEndpoint(), 5s);
    Probe p;
    p.position = {5, 5, 5};
    p.active = true;
    client.sendProbe(p);
    for (int k = 0; k < 200 && !front.takeProbe(); ++k) std::this_thread::sleep_for(5ms);
    // Before: an EncodeError thrown on the front's thread ended the process.
    front.offerFeedback({1, 10, {kNaN, 0, 0}, 0});
    front.offerFeedback({1, 11, {kInf, 0, 0}, 0});
    CommandReply tooLong;
    tooLong.message = std::string(5000, 'x');  // over its cap: cut, not thrown
    front.reply({"nobody", Command{}}, tooLong);
    CommandReply unknown;
    unknown.status = ReplyStatus(9);  // no such status: cannot be encoded, counted
    front.reply({"nobody", Command{}}, unknown);
    front.offerFeedback({1, 12, {0.5, 0, 0}, 0});
    std::optional<Feedback> fb;
    for (const auto deadline = Clock::now() + 3s; !fb && Clock::now() < deadline;)
        fb = client.waitFeedback(Clock::now() + 50ms);
    REQUIRE(fb);
    CHECK(fb->step == 12);
    CHECK(fb->force.x() == 0.5);
    const FrontStats s = front.stats();
    CHECK(s.internalErrors == 3);
    CHECK(s.lastInternalError.find("reply not sent") != std::string::npos);
}

TEST_CASE("front: a session silent for the timeout is forgotten; a client that polls keeps its own",
          "[protocol][front][sessions]") {
    FrontOptions o = ephemeral();
    o.sessionTimeout = 300ms;
    const SceneInfo scene = smallScene();
    ServerFront front(o, scene);
    ClientSession keeper;
    CHECK(keeper.connect(front.controlEndpoint(), 5s).sessionTimeoutS == Approx(0.3));
    {
        RawClient silent(front.controlEndpoint());
        silent.hello();
        CHECK(front.stats().clients == 2);
        for (const auto until = Clock::now() + 900ms; Clock::now() < until;) {
            keeper.pollFeedback();
            std::this_thread::sleep_for(10ms);
        }
        CHECK(front.stats().clients == 1);
        CHECK(front.stats().sessionsExpired == 1);
        // Forgotten: its command is refused until it says Hello again.
        const Buffer seed = seedMessage(1, {5, 5, 5});
        CHECK(silent.refusalOf(seed) == "hello first");
        silent.hello();
        silent.send(seed);
        REQUIRE(silent.next(MessageKind::CommandReply, 200ms) == std::nullopt);  // taken: the step loop answers
        CHECK(front.takeCommands().size() == 1);
    }
    CHECK(keeper.stats().keepAlives >= 2);
    CHECK(front.stats().sessionsExpired == 1);
}

TEST_CASE("front: sessions that come and go leave the table as it was", "[protocol][front][sessions]") {
    FrontOptions o = ephemeral();
    o.sessionTimeout = 2s;  // longer than 4,000 injections take under the sanitizers
    ServerFront front(o, smallScene());
    const Buffer hello = encodeHello({}), bad = probeMessage({5, 5, 5}, 1, kInf);
    for (int k = 0; k < 2000; ++k) {  // as many peers saying Hello and a bad probe, without a socket
        const std::string id = "peer-" + std::to_string(k);
        front.inject(id, hello.data(), hello.size());
        front.inject(id, bad.data(), bad.size());
    }
    CHECK(front.stats().clients == 2000);
    for (int k = 0; k < 500 && front.stats().clients > 0; ++k) std::this_thread::sleep_for(10ms);
    const FrontStats s = front.stats();
    CHECK(s.clients == 0);
    CHECK(s.sessionsOpened == 2000);
    CHECK(s.sessionsExpired == 2000);
    CHECK(s.outOfRange == 2000);
}

TEST_CASE("front: the map's edits are served from any number on, in answers within a client's cap",
          "[protocol][front][cut]") {
    ServerFront front(ephemeral(), smallScene());
    // Three yields of the most voxels an edit holds (half a MiB each) among blades: not one answer.
    auto edits = std::make_shared<std::vector<MapEdit>>();
    for (int k = 0; k < 8; ++k) {
        if (k % 3 == 1) {
            MapEdit e;
            for (std::size_t v = 0; v < kMaxEditVoxels; ++v) e.voxels.push_back(3 * v + std::uint64_t(k));
            edits->push_back(std::move(e));
        } else {
            edits->push_back({Cut{{0.5 * k, 1, 2}, {3, 0.25 * k, 1}, 0.5 + k}, {}});
        }
    }
    front.setMapEdits(edits);
    ClientSession client;
    client.connect(front.controlEndpoint(), 5s);
    RawClient early(front.controlEndpoint());  // no Hello: refused
    CHECK(early.refusalOf(encodeMapEditsRequest({0})) == "MapEditsRequest: hello first");
    const auto answer = [&](std::uint32_t first) {
        REQUIRE(client.requestMapEdits(first));
        for (const auto deadline = Clock::now() + 3s; Clock::now() < deadline; std::this_thread::sleep_for(1ms)) {
            client.pollFeedback();
            if (std::optional<MapEdits> e = client.takeMapEdits()) return *e;
        }
        FAIL("no MapEdits within 3 s");
        return MapEdits{};
    };
    MapEdits all{0, 0, {}};
    int answers = 0;
    while (all.edits.size() < edits->size() && answers < 20) {
        const MapEdits e = answer(std::uint32_t(all.edits.size()));
        ++answers;
        CHECK(e.total == edits->size());
        REQUIRE(e.first == all.edits.size());
        REQUIRE_FALSE(e.edits.empty());
        CHECK(encodeMapEdits(e).size() <= kMaxMapEditsBytes);
        all.edits.insert(all.edits.end(), e.edits.begin(), e.edits.end());
    }
    all.total = std::uint32_t(edits->size());
    CHECK(answers >= 2);
    CHECK(samples::same(all, MapEdits{0, all.total, *edits}));
    // Past the end: none, and where the list ends.
    const MapEdits none = answer(1000);
    CHECK(none.first == edits->size());
    CHECK(none.edits.empty());
    CHECK(front.stats().internalErrors == 0);
}
