#include "app/HapticLink.hpp"

#include <cstdio>

namespace bop::haptic {

using namespace std::chrono_literals;

HapticLink::HapticLink(protocol::ClientOptions options, std::string endpoint, double lostAfterS)
    : options_(std::move(options)),
      endpoint_(std::move(endpoint)),
      lostAfterS_(lostAfterS),
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

protocol::SceneInfo HapticLink::connect(std::chrono::milliseconds timeout) {
    return session_->connect(endpoint_, timeout);
}

// The loop's side: only try_lock, never a wait; what is to be said is said by the helper.
bool HapticLink::tick(double nowS, bool fed) {
    if (lostAfterS_ <= 0) return false;
    if (fed || lastFedS_ < 0) lastFedS_ = nowS;
    std::unique_lock lock(m_, std::try_to_lock);
    if (!lock.owns_lock()) return false;  // next tick
    if (!wanted_) {
        if (nowS - lastFedS_ <= lostAfterS_) return false;
        want_ = wanted_ = true;
        silentS_ = nowS - lastFedS_;
        lock.unlock();
        wake_.notify_all();
        return false;
    }
    if (fed) {  // the old session answers again (a network blip): no new one after all
        want_ = wanted_ = false;
        if (ready_ && !retired_) retired_ = std::move(ready_);  // else it waits for the next silence
        lock.unlock();
        wake_.notify_all();
        return false;
    }
    if (!ready_ || retired_) return false;  // the helper is still closing one: never here
    retired_ = std::move(session_);
    session_ = std::move(ready_);
    wanted_ = false;
    lastFedS_ = nowS;  // the new server has `lostAfterS` to answer
    taken_ = ++reconnections_;
    lock.unlock();
    wake_.notify_all();  // the helper closes the old session and says so
    return true;
}

void HapticLink::helperLoop() {
    std::unique_lock lock(m_);
    while (!stop_) {
        wake_.wait(lock, [&] { return stop_ || want_ || retired_ || taken_; });
        if (taken_) {
            std::printf("bop-haptic: connected again to %s (connection %u)\n", endpoint_.c_str(), taken_ + 1);
            std::fflush(stdout);
            taken_ = 0;
        }
        if (retired_) {
            auto old = std::move(retired_);
            lock.unlock();
            old.reset();  // closing sockets is not for the 1 kHz loop
            lock.lock();
            continue;
        }
        if (stop_ || !want_) continue;
        if (silentS_ > 0) {
            std::printf("bop-haptic: no feedback for %.1f s; connecting to %s again\n", silentS_, endpoint_.c_str());
            std::fflush(stdout);
            silentS_ = 0;
        }
        const auto attempt = std::chrono::steady_clock::now();
        lock.unlock();
        std::unique_ptr<protocol::ClientSession> fresh;
        try {
            fresh = std::make_unique<protocol::ClientSession>(options_);
            fresh->connect(endpoint_, 1s);
        } catch (const std::exception&) {  // nobody there yet: again, a second after this attempt began
            fresh.reset();
        }
        lock.lock();
        if (!fresh) {
            wake_.wait_until(lock, attempt + 1s, [&] { return stop_ || !want_; });
        } else if (want_) {
            ready_ = std::move(fresh);
            want_ = false;
        } else {  // called off meanwhile
            lock.unlock();
            fresh.reset();
            lock.lock();
        }
    }
}

}  // namespace bop::haptic
