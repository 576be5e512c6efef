// The gradient-map download (MapRequest -> MapChunk): pieces of FrontOptions::mapFile read
// straight from disk on the front's thread; and the map's edits since (MapEditsRequest ->
// MapEdits), from the list the step loop hands over. Budgets: a client gets at most 16 pieces (16 MiB) a
// second and a pass of the loop answers at most 8; further requests get an empty piece and ask
// again. So a client asking too fast, or asking and never reading, can neither hold up probes
// and feedback nor pile up more than a second's pieces at a time in its send queue.
#include "server/ServerFrontImpl.hpp"

#include <algorithm>
#include <fstream>

namespace bop::protocol {
namespace {

constexpr int kMapPiecesPerPass = 8;
constexpr int kMapPiecesPerClientSecond = 16;  // MapEdits answers count as pieces

}  // namespace

Buffer ServerFront::Impl::mapPiece(const MapRequest& r, front::Client& client) {
    MapChunk c;
    c.offset = r.offset;
    std::ifstream in;
    if (!opt.mapFile.empty()) in.open(opt.mapFile, std::ios::binary | std::ios::ate);
    if (!in) {  // no map: total 0
        c.offset = 0;
        return encodeMapChunk(c);
    }
    c.total = std::uint64_t(in.tellg());
    c.offset = std::min(r.offset, c.total);
    if (++mapPiecesThisPass > kMapPiecesPerPass || !client.mapPieces.take(Clock::now(), kMapPiecesPerClientSecond))
        return encodeMapChunk(c);  // empty: ask again
    c.data.resize(std::size_t(std::min<std::uint64_t>(r.length, c.total - c.offset)));
    in.seekg(std::streamoff(c.offset));
    in.read(reinterpret_cast<char*>(c.data.data()), std::streamsize(c.data.size()));
    c.data.resize(std::size_t(in.gcount()));
    return encodeMapChunk(c);
}

Buffer ServerFront::Impl::mapEdits(const MapEditsRequest& r, front::Client& client) {
    std::shared_ptr<const std::vector<MapEdit>> all;
    {
        std::lock_guard slots(inbound.m);
        all = inbound.mapEdits;
    }
    MapEdits answer;
    answer.total = all ? std::uint32_t(all->size()) : 0;
    answer.first = std::min(r.first, answer.total);
    if (answer.first == answer.total || ++mapPiecesThisPass > kMapPiecesPerPass ||
        !client.mapPieces.take(Clock::now(), kMapPiecesPerClientSecond))
        return encodeMapEdits(answer);  // none, or ask again
    std::size_t bytes = 0;              // one edit alone fits: its voxels are at most kMaxEditVoxels
    for (std::size_t i = answer.first; i < all->size() && answer.edits.size() < kMaxEditsPerMessage; ++i) {
        bytes += mapEditWireBytes((*all)[i].voxels.size());
        if (bytes > kMaxMapEditsPayload) break;
        answer.edits.push_back((*all)[i]);
    }
    return encodeMapEdits(answer);
}

}  // namespace bop::protocol
