#include "app/HapticLink.hpp"

#include <cstdio>

namespace bop::haptic {

using namespace std::chrono_literals;

HapticLink::HapticLink(protocol::ClientOptions options, std::string endpoint, double lostAfterS)
    : options_(std::move(options)), endpoint_(std::move(endpoint)), lostAfterS_(lostAfterS),
      session_(std::make_unique<protocol::ClientSession>(options_)) {
    if (lostAfterS_ > 0) helper_ = std::thread([this] { helperLoop(); });
}

HapticLink::~HapticLink() {
    {
        std::lock_guard lock(m_);
        stop_ = true;
    }
    wake_.notify_all();
    if (helper_.joinable()) helper_.join();
}

protocol::SceneInfo HapticLink::connect(std::chrono::milliseconds timeout) { return session_->connect(endpoint_, timeout); }

bool HapticLink::tick(double nowS, bool fed) {
    if (lostAfterS_ <= 0) return false;
    if (fed || lastFedS_ < 0) lastFedS_ = nowS;
    if (!wanted_ && nowS - lastFedS_ > lostAfterS_) {
        std::unique_lock lock(m_, std::try_to_lock);
        if (lock.owns_lock()) {  // else next tick: the loop never waits for the helper
            want_ = wanted_ = true;
            std::printf("bop-haptic: no feedback for %.1f s; connecting to %s again\n", nowS - lastFedS_, endpoint_.c_str());
            std::fflush(stdout);
            lock.unlock();
            wake_.notify_all();
        }
        return false;
    }
    if (!wanted_) return false;
    std::unique_lock lock(m_, std::try_to_lock);
    if (!lock.owns_lock() || !ready_) return false;
    retired_ = std::move(session_);
    session_ = std::move(ready_);
    wanted_ = false;
    lastFedS_ = nowS;  // the new server has `lostAfterS` to answer
    ++reconnections_;
    lock.unlock();
    wake_.notify_all();  // the helper closes the old session
    std::printf("bop-haptic: connected again to %s (connection %u)\n", endpoint_.c_str(), reconnections_ + 1);
    std::fflush(stdout);
    return true;
}

void HapticLink::helperLoop() {
    std::unique_lock lock(m_);
    while (!stop_) {
        wake_.wait(lock, [&] { return stop_ || want_ || retired_; });
        if (retired_) {
            auto old = std::move(retired_);
            lock.unlock();
            old.reset();  // closing sockets is not for the 1 kHz loop
            lock.lock();
            continue;
        }
        if (stop_ || !want_) continue;
        lock.unlock();
        std::unique_ptr<protocol::ClientSession> fresh;
        try {
            fresh = std::make_unique<protocol::ClientSession>(options_);
            fresh->connect(endpoint_, 1s);
        } catch (const std::exception&) {  // nobody there yet: try again in a second
            fresh.reset();
        }
        lock.lock();
        if (fresh) {
            ready_ = std::move(fresh);
            want_ = false;
        } else {
            wake_.wait_for(lock, 1s, [&] { return stop_; });
        }
    }
}

}  // namespace bop::haptic
