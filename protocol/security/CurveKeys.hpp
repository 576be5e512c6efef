#pragma once
// CURVE key files (ZeroMQ's encryption and server authentication): one z85 key of 40 characters
// per file (32 key bytes), optionally followed by a line end. bop-keys writes them as a pair,
// PREFIX.key (secret, mode 0600) and PREFIX.pub (public, for whoever connects to the holder).
#include <string>

namespace bop::protocol {

inline constexpr std::size_t kCurveKeyChars = 40;  // z85 text of a 32-byte key

struct CurveKeyPair {
    std::string publicKey;  // z85, 40 characters
    std::string secretKey;  // z85, 40 characters
};

// A fresh random key pair (zmq_curve_keypair); bop::Error if this libzmq was built without CURVE.
CurveKeyPair makeCurveKeyPair();

// True when `key` is 40 characters of the z85 alphabet that decode to 32 bytes.
bool isCurveKey(const std::string& key);

// The key in the file at `path`: 40 z85 characters, then nothing but an optional line end.
// bop::Error naming the file when it cannot be read or does not hold exactly one such key.
std::string readCurveKey(const std::string& path);

// Writes PREFIX.key (the secret key, created with mode 0600 and set to it) and PREFIX.pub (the
// public key, 0644), each the key and a newline. Refuses to replace existing files unless
// `overwrite`: a lost secret key cannot be recovered, and clients trust the public one.
// bop::Error naming the file on failure.
void writeCurveKeyFiles(const std::string& prefix, const CurveKeyPair& keys, bool overwrite = false);

}  // namespace bop::protocol
