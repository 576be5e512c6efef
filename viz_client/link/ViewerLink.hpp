#pragma once
// The viewer's link to the server, on a thread of its own so that drawing never waits on the
// network: it connects (retrying with a doubling wait, 1 s up to 8 s), keeps the client
// library's receiver thread running (the newest whole frame in a slot), sends the panel's
// commands one at a time and logs their replies, sends the newest mouse probe (again every
// 200 ms while it is on, so the server keeps sending feedback), times the probe round trip from
// the feedback, and reconnects when no frame has come for `lostAfter`.
#include "client/ClientSession.hpp"
#include "client/RoundTrip.hpp"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace bop::viz {

enum class LinkState { Connecting, Connected, Reconnecting, GaveUp };
const char* linkStateName(LinkState s);

struct LinkOptions {
    std::chrono::seconds lostAfter{10};              // no frame for this long: connect again
    std::chrono::milliseconds giveUpAfter{0};        // stop trying after this long without a connection; 0 = never
    std::chrono::milliseconds commandTimeout{2000};  // wait for a command's reply
};

struct LinkStatus {
    LinkState state = LinkState::Connecting;
    int attempt = 0;                                   // connection attempts since the last success
    std::string message;                               // the last connection error, or where we are connected
    std::uint64_t sceneVersion = 0;                    // increases with every new connection (a new SceneInfo)
    std::vector<std::string> replies;                  // the newest command replies, oldest first
    std::optional<protocol::Feedback> feedback;        // the newest
    double rttP50Ms = 0, rttP99Ms = 0, rttLastMs = 0;  // probe -> feedback, ms
    std::size_t rttCount = 0;
    protocol::ClientStats client;
};

class ViewerLink {
public:
    ViewerLink(std::string endpoint, protocol::ClientOptions client, LinkOptions options = {});
    ~ViewerLink();  // stops the thread: at once, or after a connection attempt (1 s) or a command (2 s) under way
    ViewerLink(const ViewerLink&) = delete;
    ViewerLink& operator=(const ViewerLink&) = delete;

    LinkStatus status() const;
    std::shared_ptr<const protocol::SceneInfo> scene() const;  // null before the first connection
    protocol::LatestFrame latestFrame() const;                 // never waits
    void submit(protocol::Command command);                    // queued; the request id is set here
    void setProbe(protocol::Probe probe);                      // the newest wins; its sequence number is set here

private:
    void run();
    void loop();     // connect, serve, connect again; until stopped or given up
    bool connect();  // one attempt; false on failure (the status says why)
    void serve();    // while connected: commands, probe, feedback, lost detection

    const std::string endpoint_;
    const LinkOptions options_;
    protocol::ClientSession session_;
    mutable std::mutex m_;
    std::condition_variable wake_;
    LinkStatus status_;
    std::shared_ptr<const protocol::SceneInfo> scene_;
    std::deque<protocol::Command> commands_;
    std::optional<protocol::Probe> probe_;  // not yet sent
    std::uint64_t nextRequest_ = 1, probeSeq_ = 0;
    protocol::RoundTrip roundTrip_;
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

}  // namespace bop::viz
