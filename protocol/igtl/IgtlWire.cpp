#include "IgtlWire.hpp"

#include <array>
#include <cmath>
#include <cstring>

namespace bop::igtl {
namespace {

constexpr std::uint64_t kPolynomial = 0x42F0E1EBA9EA3693ull;

constexpr std::array<std::uint64_t, 256> kCrcTable = [] {
    std::array<std::uint64_t, 256> t{};
    for (std::uint64_t b = 0; b < 256; ++b) {
        std::uint64_t c = b << 56;
        for (int k = 0; k < 8; ++k) c = (c & (1ull << 63)) ? (c << 1) ^ kPolynomial : c << 1;
        t[b] = c;
    }
    return t;
}();

std::uint64_t bigEndian(const std::uint8_t* p, int bytes) {
    std::uint64_t v = 0;
    for (int k = 0; k < bytes; ++k) v = v << 8 | p[k];
    return v;
}

void putBigEndian(std::vector<std::uint8_t>& out, std::uint64_t v, int bytes) {
    for (int k = bytes - 1; k >= 0; --k) out.push_back(std::uint8_t(v >> (8 * k)));
}

// A NUL-padded ASCII field: printable characters, then NULs only.
bool readName(const std::uint8_t* p, std::size_t size, std::string& out) {
    std::size_t n = 0;
    while (n < size && p[n] != 0) {
        if (p[n] < 0x20 || p[n] > 0x7e) return false;
        ++n;
    }
    for (std::size_t k = n; k < size; ++k)
        if (p[k] != 0) return false;
    out.assign(reinterpret_cast<const char*>(p), n);
    return true;
}

}  // namespace

std::uint64_t crc64(std::span<const std::uint8_t> bytes) {
    std::uint64_t c = 0;
    for (const std::uint8_t b : bytes) c = kCrcTable[(c >> 56 ^ b) & 0xff] ^ (c << 8);
    return c;
}

bool readHeader(std::span<const std::uint8_t, kHeaderSize> bytes, Header& out, std::string& error,
                std::uint64_t maxBody) {
    const std::uint8_t* p = bytes.data();
    out.version = std::uint16_t(bigEndian(p, 2));
    if (out.version < 1 || out.version > 2) {
        error = "header version " + std::to_string(out.version) + ", expected 1 or 2";
        return false;
    }
    if (!readName(p + 2, kTypeSize, out.type) || out.type.empty()) {
        error = "message type is not printable ASCII padded with NULs";
        return false;
    }
    if (!readName(p + 2 + kTypeSize, kDeviceSize, out.device)) {
        error = "device name of a " + out.type + " is not printable ASCII padded with NULs";
        return false;
    }
    out.timestamp = bigEndian(p + 34, 8);
    out.bodySize = bigEndian(p + 42, 8);
    out.crc = bigEndian(p + 50, 8);
    if (out.bodySize > maxBody) {
        error = out.type + " '" + out.device + "' announces a body of " + std::to_string(out.bodySize) +
                " bytes, more than the " + std::to_string(maxBody) + " accepted";
        return false;
    }
    return true;
}

bool readContent(const Header& h, std::span<const std::uint8_t> body, std::span<const std::uint8_t>& content,
                 std::string& error) {
    const std::string what = h.type + " '" + h.device + "'";
    if (body.size() != h.bodySize) {
        error = what + ": body of " + std::to_string(body.size()) + " bytes, header says " + std::to_string(h.bodySize);
        return false;
    }
    if (crc64(body) != h.crc) {
        error = what + ": body CRC-64 does not match the header's";
        return false;
    }
    content = body;
    if (h.version < 2) return true;
    // Header version 2 (protocol version 3): extended header (its size uint16, the metadata header's size uint16, the
    // metadata's size uint32, message id uint32), content, metadata header, metadata.
    if (body.size() < 12) {
        error = what + ": header version 2 body shorter than its 12-byte extended header";
        return false;
    }
    const std::uint64_t ext = bigEndian(body.data(), 2), metaHeader = bigEndian(body.data() + 2, 2),
                        meta = bigEndian(body.data() + 4, 4);
    if (ext < 12 || ext + metaHeader + meta > body.size()) {
        error = what + ": extended header (" + std::to_string(ext) + " bytes) and metadata (" +
                std::to_string(metaHeader + meta) + ") do not fit its body of " + std::to_string(body.size());
        return false;
    }
    content = body.subspan(ext, body.size() - ext - metaHeader - meta);
    return true;
}

bool readTransform(std::span<const std::uint8_t> content, Eigen::Matrix4d& out, std::string& error) {
    if (content.size() != 48) {
        error = "TRANSFORM content of " + std::to_string(content.size()) + " bytes, expected 48 (12 float32)";
        return false;
    }
    out.setIdentity();
    for (int k = 0; k < 12; ++k) {
        const std::uint32_t bits = std::uint32_t(bigEndian(content.data() + 4 * k, 4));
        float v;
        std::memcpy(&v, &bits, sizeof v);
        if (!std::isfinite(v)) {
            error = "TRANSFORM value " + std::to_string(k + 1) + " of 12 is not a finite number";
            return false;
        }
        out(k < 9 ? k % 3 : k - 9, k < 9 ? k / 3 : 3) = double(v);
    }
    return true;
}

std::vector<std::uint8_t> encodeMessage(const std::string& type, const std::string& device,
                                        std::span<const std::uint8_t> body, std::uint16_t version,
                                        std::uint64_t timestamp) {
    std::vector<std::uint8_t> out;
    out.reserve(kHeaderSize + body.size());
    putBigEndian(out, version, 2);
    for (std::size_t k = 0; k < kTypeSize; ++k) out.push_back(k < type.size() ? std::uint8_t(type[k]) : 0);
    for (std::size_t k = 0; k < kDeviceSize; ++k) out.push_back(k < device.size() ? std::uint8_t(device[k]) : 0);
    putBigEndian(out, timestamp, 8);
    putBigEndian(out, body.size(), 8);
    putBigEndian(out, crc64(body), 8);
    out.insert(out.end(), body.begin(), body.end());
    return out;
}

std::vector<std::uint8_t> transformBody(const Eigen::Matrix4d& m) {
    std::vector<std::uint8_t> out;
    for (int k = 0; k < 12; ++k) {
        const float v = float(m(k < 9 ? k % 3 : k - 9, k < 9 ? k / 3 : 3));
        std::uint32_t bits;
        std::memcpy(&bits, &v, sizeof bits);
        putBigEndian(out, bits, 4);
    }
    return out;
}

}  // namespace bop::igtl
