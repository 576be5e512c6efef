#pragma once
// OpenIGTLink's wire format, read from untrusted bytes as its published specification lays it out
// (openigtlink.org, "Protocol"): a 58-byte header, big-endian (header version uint16, type
// char[12], device name char[20], time stamp uint64, body size uint64, CRC-64 of the body uint64),
// then the body. Header version 1 is the format of protocol versions 1 and 2; header version 2,
// protocol version 3's, starts the body with an extended header and ends it with metadata. Everything bop-igtl receives
// goes through here: a header or body that breaks a rule is refused with the reason, never read past its end, and a
// body larger than the reader allows is refused before it is read. Outgoing messages are packed by the reference
// library (IgtlMessages.hpp); these encoders are for tests and the fuzz seeds.
#include <Eigen/Core>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace bop::igtl {

constexpr std::size_t kHeaderSize = 58;
constexpr std::size_t kTypeSize = 12, kDeviceSize = 20;
// What bop-igtl reads: transforms, positions, status and queries, none near this.
constexpr std::uint64_t kMaxBodyBytes = 1u << 20;

struct Header {
    std::uint16_t version = 0;
    std::string type;    // "TRANSFORM", ...
    std::string device;  // "StylusTipToReference", ...
    std::uint64_t timestamp = 0;
    std::uint64_t bodySize = 0;
    std::uint64_t crc = 0;
};

// The CRC-64 OpenIGTLink puts in its headers (ECMA-182, polynomial 0x42F0E1EBA9EA3693, MSB first,
// initial value 0, no final xor).
std::uint64_t crc64(std::span<const std::uint8_t> bytes);

// Reads a header from its 58 bytes. False with `error` set when the version is not 1 or 2, the
// type or the device name is not printable ASCII padded with NULs (the type not empty), or the
// body is larger than maxBody.
bool readHeader(std::span<const std::uint8_t, kHeaderSize> bytes, Header& out, std::string& error,
                std::uint64_t maxBody = kMaxBodyBytes);

// The message's content from its body (header.bodySize bytes): the body's CRC checked, and in
// header version 2 the extended header and the metadata taken off. False with `error` set otherwise.
bool readContent(const Header& header, std::span<const std::uint8_t> body, std::span<const std::uint8_t>& content,
                 std::string& error);

// A TRANSFORM's content: 12 float32, the rotation's columns then the translation (mm). False
// with `error` set unless it is 48 bytes of finite numbers.
bool readTransform(std::span<const std::uint8_t> content, Eigen::Matrix4d& out, std::string& error);

// A whole message: header (its CRC over `body`) and body, with header `version` (1: the body is the
// content; 2: the caller's body holds the extended header and metadata).
std::vector<std::uint8_t> encodeMessage(const std::string& type, const std::string& device,
                                        std::span<const std::uint8_t> body, std::uint16_t version = 1,
                                        std::uint64_t timestamp = 0);
// A TRANSFORM's 48-byte body from a 4 x 4 matrix (its top three rows).
std::vector<std::uint8_t> transformBody(const Eigen::Matrix4d& m);

}  // namespace bop::igtl
