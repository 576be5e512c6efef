#pragma once
// bop-haptic's session with the server, kept up without the device loop ever waiting on it. When
// no feedback has come for `lostAfterS` (the server died, restarted or the network went), a
// helper thread connects a fresh session to the same endpoint, an attempt a second (each waits
// up to 1 s for the server's answer); the loop goes on meanwhile with the old session (its probes
// go nowhere; the force model's safety gain has already taken the force to 0) and takes the new
// one over at the first tick after it is ready, unless the old one answers again first. Old
// sessions are closed, and what happens is printed, on the helper thread. The gradient map is not
// downloaded again: a restarted server is taken to serve the same scene.
#include "client/ClientSession.hpp"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

namespace bop::haptic {

class HapticLink {
public:
    // lostAfterS <= 0: never reconnect (the session stays as connect() made it).
    HapticLink(protocol::ClientOptions options, std::string endpoint, double lostAfterS);
    ~HapticLink();  // stops the helper thread (within one connect attempt, about a second)
    HapticLink(const HapticLink&) = delete;
    HapticLink& operator=(const HapticLink&) = delete;

    // The first session, waited for; bop::Error naming the endpoint when none comes in `timeout`.
    protocol::SceneInfo connect(std::chrono::milliseconds timeout);
    protocol::ClientSession& session() { return *session_; }

    // Once per loop tick, `nowS` on any steady clock in s, `fed` when feedback came this tick.
    // Never waits. True when a new session took over at this tick.
    bool tick(double nowS, bool fed);
    unsigned reconnections() const { return reconnections_; }

private:
    void helperLoop();

    protocol::ClientOptions options_;
    std::string endpoint_;
    double lostAfterS_;
    std::unique_ptr<protocol::ClientSession> session_;
    double lastFedS_ = -1;  // the loop's alone
    unsigned reconnections_ = 0;

    // Under m_:
    bool wanted_ = false;  // a reconnection was asked of the helper and not yet taken over or called off
    double silentS_ = 0;   // how long the silence was when it was asked (to print)
    unsigned taken_ = 0;   // a new session was taken over: its connection count less one (to print)
    std::mutex m_;
    std::condition_variable wake_;
    bool want_ = false, stop_ = false;  // want_: the helper is to connect
    std::unique_ptr<protocol::ClientSession> ready_, retired_;
    std::thread helper_;
};

}  // namespace bop::haptic
