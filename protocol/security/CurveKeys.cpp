#include "security/CurveKeys.hpp"

#include "bop/common/Error.hpp"

#include <zmq.h>

#include <array>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string_view>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace bop::protocol {
namespace {

// The 85 characters of Z85 (ZeroMQ RFC 32), in value order.
constexpr std::string_view kZ85Alphabet =
    "0123456789abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ.-:+=^!/*?&<>()[]{}@%$#";

// A key file is 40 characters and a line end; anything much larger is not a key file, and is not
// read into memory whole.
constexpr std::size_t kMaxKeyFileBytes = 256;

// Creates (or, with overwrite, truncates) `path` with `mode` and writes `text`.
void writeFile(const std::string& path, const std::string& text, mode_t mode, bool overwrite) {
    const int flags = O_WRONLY | O_CREAT | O_CLOEXEC | (overwrite ? O_TRUNC : O_EXCL);
    const int fd = ::open(path.c_str(), flags, mode);
    if (fd < 0) {
        if (errno == EEXIST) throw Error(path, "already exists; not replaced (a lost secret key cannot be recovered)");
        throw Error(path, std::string("cannot create: ") + std::strerror(errno));
    }
    // An existing file keeps its mode under O_TRUNC: narrow it before the secret goes in.
    int err = ::fchmod(fd, mode) == 0 ? 0 : errno;
    for (std::size_t done = 0; !err && done < text.size();) {
        const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
        if (n < 0 && errno != EINTR) err = errno;
        if (n > 0) done += std::size_t(n);
    }
    if (::close(fd) != 0 && !err) err = errno;
    if (err) throw Error(path, std::string("cannot write: ") + std::strerror(err));
}

}  // namespace

CurveKeyPair makeCurveKeyPair() {
    std::array<char, kCurveKeyChars + 1> pub{}, sec{};  // z85 text and its terminating NUL
    if (zmq_curve_keypair(pub.data(), sec.data()) != 0)
        throw Error("CURVE", std::string("cannot make a key pair: ") + zmq_strerror(zmq_errno()) +
                                 " (libzmq without CURVE support?)");
    return {std::string(pub.data()), std::string(sec.data())};
}

bool isCurveKey(const std::string& key) {
    if (key.size() != kCurveKeyChars) return false;
    for (const char c : key)
        if (kZ85Alphabet.find(c) == std::string_view::npos) return false;
    std::array<std::uint8_t, 32> bytes{};
    return zmq_z85_decode(bytes.data(), key.c_str()) != nullptr;
}

std::string readCurveKey(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw Error(path, "is a folder, expected a CURVE key file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path, std::string("cannot read CURVE key file: ") + std::strerror(errno));
    std::string text;
    text.resize(kMaxKeyFileBytes + 1);
    in.read(text.data(), std::streamsize(text.size()));
    text.resize(std::size_t(in.gcount()));
    if (in.bad()) throw Error(path, "cannot read CURVE key file");
    if (text.size() > kMaxKeyFileBytes)
        throw Error(path, "more than " + std::to_string(kMaxKeyFileBytes) +
                              " bytes; expected one 40-character z85 CURVE key (as bop-keys writes)");
    if (text.ends_with("\r\n"))
        text.resize(text.size() - 2);
    else if (text.ends_with('\n'))
        text.pop_back();
    if (text.size() != kCurveKeyChars)
        throw Error(path, std::to_string(text.size()) +
                              " characters; expected a 40-character z85 CURVE key "
                              "(and at most a line end)");
    if (!isCurveKey(text))
        throw Error(path, "not a z85 CURVE key (40 characters of the z85 alphabet, as bop-keys writes)");
    return text;
}

void writeCurveKeyFiles(const std::string& prefix, const CurveKeyPair& keys, bool overwrite) {
    if (!isCurveKey(keys.publicKey) || !isCurveKey(keys.secretKey))
        throw Error(prefix, "not a z85 CURVE key pair (40 characters each)");
    const std::string secretPath = prefix + ".key", publicPath = prefix + ".pub";
    // Check both before writing either, so that a refusal never leaves half a pair behind.
    if (!overwrite)
        for (const std::string& p : {secretPath, publicPath}) {
            std::error_code ec;
            if (std::filesystem::exists(std::filesystem::symlink_status(p, ec)))
                throw Error(p, "already exists; not replaced (a lost secret key cannot be recovered)");
        }
    writeFile(secretPath, keys.secretKey + "\n", S_IRUSR | S_IWUSR, overwrite);
    writeFile(publicPath, keys.publicKey + "\n", S_IRUSR | S_IWUSR | S_IRGRP | S_IROTH, overwrite);
}

}  // namespace bop::protocol
