#include "link/ViewerLink.hpp"

#include "bop/common/Error.hpp"

namespace bop::viz {
namespace {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;
constexpr std::size_t kReplyLog = 8;
constexpr auto kProbeRefresh = 200ms;  // re-send an active probe at least this often

double seconds(Clock::time_point t) {
    return std::chrono::duration<double>(t.time_since_epoch()).count();
}

const char* statusName(protocol::ReplyStatus s) {
    switch (s) {
        case protocol::ReplyStatus::Ok:
            return "ok";
        case protocol::ReplyStatus::Rejected:
            return "rejected";
        case protocol::ReplyStatus::Unsupported:
            return "unsupported";
        case protocol::ReplyStatus::ReadOnly:
            return "read-only";
        case protocol::ReplyStatus::Failed:
            return "failed";
    }
    return "?";
}

const char* commandName(const protocol::CommandBody& b) {
    static const char* const names[] = {"seed",      "birth",      "parameter", "run",
                                        "map frame", "checkpoint", "record",    "cut"};
    static_assert(std::size(names) == std::variant_size_v<protocol::CommandBody>, "a name for every command");
    return names[b.index()];
}

}  // namespace

const char* linkStateName(LinkState s) {
    switch (s) {
        case LinkState::Connecting:
            return "connecting";
        case LinkState::Connected:
            return "connected";
        case LinkState::Reconnecting:
            return "reconnecting";
        case LinkState::GaveUp:
            return "gave up";
    }
    return "?";
}

ViewerLink::ViewerLink(std::string endpoint, protocol::ClientOptions client, LinkOptions options)
    : endpoint_(std::move(endpoint)), options_(options), session_(std::move(client)) {
    thread_ = std::thread([this] { run(); });
}

ViewerLink::~ViewerLink() {
    {
        std::lock_guard lock(m_);  // so that a waiting thread cannot miss it
        stop_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
}

LinkStatus ViewerLink::status() const {
    std::lock_guard lock(m_);
    LinkStatus s = status_;
    s.client = session_.stats();
    return s;
}

std::shared_ptr<const protocol::SceneInfo> ViewerLink::scene() const {
    std::lock_guard lock(m_);
    return scene_;
}

protocol::LatestFrame ViewerLink::latestFrame() const {
    return session_.latestFrame();
}

void ViewerLink::submit(protocol::Command command) {
    std::lock_guard lock(m_);
    command.requestId = nextRequest_++;
    commands_.push_back(std::move(command));
    wake_.notify_all();
}

void ViewerLink::setProbe(protocol::Probe probe) {
    std::lock_guard lock(m_);
    probe_ = probe;
    wake_.notify_all();
}

bool ViewerLink::connect() {
    try {
        protocol::SceneInfo s = session_.connect(endpoint_, 1s);
        session_.startReceiver();
        std::lock_guard lock(m_);
        scene_ = std::make_shared<const protocol::SceneInfo>(std::move(s));
        status_.state = LinkState::Connected;
        status_.attempt = 0;
        status_.message = "connected to " + endpoint_;
        ++status_.sceneVersion;
        return true;
    } catch (const std::exception& e) {
        std::lock_guard lock(m_);
        ++status_.attempt;
        status_.message = e.what();
        return false;
    }
}

void ViewerLink::run() {
    try {
        loop();
    } catch (const std::exception& e) {  // nothing leaves the thread: the drawing loop sees why it ended
        std::lock_guard lock(m_);
        status_.state = LinkState::GaveUp;
        status_.message = e.what();
    }
}

void ViewerLink::loop() {
    auto wait = 1s;
    auto since = Clock::now();
    while (!stop_) {
        if (connect()) {
            std::string why = "no frame for " + std::to_string(options_.lostAfter.count()) + " s";
            try {
                serve();
            } catch (const std::exception& e) {  // a socket failing: the link is lost, not the viewer
                why = e.what();
            }
            if (stop_) return;
            if (const std::string e = session_.receiverError(); !e.empty()) why = e;
            std::lock_guard lock(m_);
            status_.state = LinkState::Reconnecting;
            status_.message = why + "; reconnecting";
            wait = 1s;
            since = Clock::now();
            continue;
        }
        if (options_.giveUpAfter.count() > 0 && Clock::now() - since > options_.giveUpAfter) {
            std::lock_guard lock(m_);
            status_.state = LinkState::GaveUp;
            return;
        }
        std::unique_lock lock(m_);
        wake_.wait_for(lock, wait, [&] { return stop_.load(); });
        wait = std::min(2 * wait, std::chrono::seconds(8));
    }
}

void ViewerLink::serve() {
    std::uint64_t seenFrames = 0;
    auto lastFrame = Clock::now(), lastProbe = Clock::now();
    std::optional<protocol::Probe> active;  // the probe last sent, while it is on
    while (!stop_) {
        std::optional<protocol::Command> command;
        std::optional<protocol::Probe> probe;
        {
            std::unique_lock lock(m_);
            wake_.wait_for(lock, 2ms, [&] { return stop_ || !commands_.empty() || probe_; });
            if (!commands_.empty()) command = std::move(commands_.front()), commands_.pop_front();
            probe.swap(probe_);
        }
        const auto now = Clock::now();
        if (!probe && active && now - lastProbe > kProbeRefresh) probe = active;
        if (probe) {
            probe->seq = ++probeSeq_;  // ours, increasing over refreshes and reconnections
            session_.sendProbe(*probe);
            lastProbe = now;
            active = probe->active ? probe : std::nullopt;
            std::lock_guard lock(m_);
            roundTrip_.sent(probe->seq, seconds(now));
        }
        if (command) {
            std::string line = commandName(command->body);
            try {
                const protocol::CommandReply r = session_.sendCommand(*command, options_.commandTimeout);
                line += std::string(": ") + statusName(r.status) + " at step " + std::to_string(r.step) +
                        (r.message.empty() ? "" : " (" + r.message + ")");
            } catch (const std::exception& e) {
                line += std::string(": ") + e.what();
            }
            std::lock_guard lock(m_);
            status_.replies.push_back(line);
            if (status_.replies.size() > kReplyLog) status_.replies.erase(status_.replies.begin());
        }
        while (const auto fb = session_.pollFeedback()) {
            std::lock_guard lock(m_);
            roundTrip_.feedback(fb->probeSeq, seconds(Clock::now()));
            status_.feedback = fb;
            status_.rttCount = roundTrip_.count();
            status_.rttP50Ms = roundTrip_.percentileMs(50);
            status_.rttP99Ms = roundTrip_.percentileMs(99);
            status_.rttLastMs = roundTrip_.lastMs();
        }
        const std::uint64_t frames = session_.latestFrame().count;
        if (frames != seenFrames) seenFrames = frames, lastFrame = now;
        if (now - lastFrame > options_.lostAfter || !session_.receiverError().empty()) return;
    }
}

}  // namespace bop::viz
