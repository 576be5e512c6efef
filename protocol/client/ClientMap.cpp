// The gradient-map download of a haptic client (MapRequest -> MapChunk, docs/protocol.md), and
// the map's edits since (MapEditsRequest -> MapEdits).
#include "bop/common/Error.hpp"
#include "client/ClientSessionImpl.hpp"
#include "codec/Codec.hpp"

#include <thread>
#include <utility>

namespace bop::protocol {

std::vector<std::uint8_t> ClientSession::downloadMap(
    std::uint64_t maxBytes, std::chrono::milliseconds timeout,
    const std::function<void(std::uint64_t, std::uint64_t)>& progress) {
    Impl& d = *impl_;
    if (!d.dealer) throw std::logic_error("ClientSession::downloadMap before connect");
    const std::uint64_t announced = d.scene.mapBytes;
    if (announced == 0) throw Error(d.controlEndpoint, "the server offers no gradient map (SceneInfo map_bytes 0)");
    if (announced > maxBytes)
        throw Error(d.controlEndpoint, "the gradient map is " + std::to_string(announced) + " bytes, over the " +
                                           std::to_string(maxBytes) + " this client accepts");
    std::vector<std::uint8_t> file;
    std::uint64_t total = announced;
    int idle = 0;  // answers in a row that brought nothing
    while (file.size() < total) {
        if (idle > 5000)  // 10 s of empty answers (2 ms apart), or a file that keeps changing
            throw Error(d.controlEndpoint, "the gradient-map download makes no progress");
        const MapRequest want{file.size(),
                              std::uint32_t(std::min<std::uint64_t>(kMaxMapPieceBytes, total - file.size()))};
        const Buffer b = encodeMapRequest(want);
        if (!d.dealer->send(zmq::buffer(b), zmq::send_flags::dontwait))
            throw Error(d.controlEndpoint, "cannot queue a map request (send queue full)");
        std::optional<MapChunk> piece;
        d.pumpControl(std::chrono::steady_clock::now() + timeout, [&](const zmq::message_t& msg) {
            const auto* data = static_cast<const std::uint8_t*>(msg.data());
            if (messageKind(data, msg.size()) != MessageKind::MapChunk) {
                d.takeControl(msg, nullptr);  // feedback and SceneInfo meanwhile are kept
                return false;
            }
            auto c = decodeMapChunk(data, msg.size());
            if (!c) {
                d.countMalformed();
                return false;
            }
            if (c.value.offset != want.offset) return false;  // an answer to an earlier request
            piece = std::move(c.value);
            return true;
        });
        if (!piece)
            throw Error(d.controlEndpoint, "no gradient-map piece at byte " + std::to_string(want.offset) + " within " +
                                               std::to_string(timeout.count()) + " ms");
        if (piece->total == 0) throw Error(d.controlEndpoint, "the server has no gradient map to give");
        if (piece->total > maxBytes)
            throw Error(d.controlEndpoint, "the gradient map grew to " + std::to_string(piece->total) + " bytes");
        if (piece->total != total) {  // the server's file changed: start again
            total = piece->total;
            file.clear();
            ++idle;
            continue;
        }
        idle = piece->data.empty() ? idle + 1 : 0;
        if (piece->data.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(2));  // busy: ask again
        file.insert(file.end(), piece->data.begin(), piece->data.end());
        if (progress) progress(file.size(), total);
    }
    return file;
}

bool ClientSession::requestMapEdits(std::uint32_t first) {
    Impl& d = *impl_;
    if (!d.dealer) throw std::logic_error("ClientSession::requestMapEdits before connect");
    const Buffer b = encodeMapEditsRequest({first});
    if (!d.dealer->send(zmq::buffer(b), zmq::send_flags::dontwait)) return false;
    d.lastSent = std::chrono::steady_clock::now();
    return true;
}

std::optional<MapEdits> ClientSession::takeMapEdits() {
    return std::exchange(impl_->mapEdits, std::nullopt);
}

}  // namespace bop::protocol
