#include "bop/common/Npy.hpp"

#include "bop/common/Error.hpp"

#include <bit>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>

#include <fcntl.h>
#include <unistd.h>

namespace bop {

static_assert(std::endian::native == std::endian::little, "Npy.cpp writes host bytes as little-endian data");

namespace {

const char kMagic[] = "\x93NUMPY";  // 6 bytes, then major and minor version bytes
constexpr std::size_t kMagicSize = 6;
constexpr std::size_t kAlign = 64;  // data offset alignment, bytes

[[noreturn]] void throwErrno(const std::string& path, int err) {
    throw Error(path, std::string("cannot write: ") + std::strerror(err));
}

std::string shapeText(const std::vector<std::size_t>& shape) {
    std::string s = "(";
    for (std::size_t i = 0; i < shape.size(); ++i) {
        if (i > 0) s += ", ";
        s += std::to_string(shape[i]);
    }
    if (shape.size() == 1) s += ",";
    return s + ")";
}

std::size_t product(const std::vector<std::size_t>& shape) {
    std::size_t n = 1;
    for (std::size_t d : shape) n *= d;
    return n;
}

// Value text following 'key': in the header dict, or npos.
std::size_t findValue(const std::string& header, const std::string& key) {
    std::size_t p = header.find("'" + key + "'");
    if (p == std::string::npos) return p;
    p = header.find(':', p);
    if (p == std::string::npos) return p;
    ++p;
    while (p < header.size() && header[p] == ' ') ++p;
    return p;
}

// Parses the header dict; fills descr and shape, returns fortran_order.
bool parseHeader(const std::string& path, const std::string& header, NpyArray& out) {
    std::size_t p = findValue(header, "descr");
    if (p == std::string::npos || p >= header.size() || (header[p] != '\'' && header[p] != '"'))
        throw Error(path, "malformed .npy header: no 'descr' string (structured dtypes unsupported)");
    const char quote = header[p];
    std::size_t e = header.find(quote, p + 1);
    if (e == std::string::npos) throw Error(path, "malformed .npy header: unterminated 'descr'");
    out.descr = header.substr(p + 1, e - p - 1);

    p = findValue(header, "fortran_order");
    if (p == std::string::npos) throw Error(path, "malformed .npy header: no 'fortran_order'");
    bool fortran = false;
    if (header.compare(p, 4, "True") == 0)
        fortran = true;
    else if (header.compare(p, 5, "False") != 0)
        throw Error(path, "malformed .npy header: 'fortran_order' is neither True nor False");

    p = findValue(header, "shape");
    if (p == std::string::npos || p >= header.size() || header[p] != '(')
        throw Error(path, "malformed .npy header: no 'shape' tuple");
    e = header.find(')', p);
    if (e == std::string::npos) throw Error(path, "malformed .npy header: unterminated 'shape'");
    out.shape.clear();
    std::size_t i = p + 1;
    while (i < e) {
        const char c = header[i];
        if (c >= '0' && c <= '9') {
            std::size_t v = 0;
            while (i < e && header[i] >= '0' && header[i] <= '9') {
                v = v * 10 + std::size_t(header[i] - '0');
                ++i;
            }
            out.shape.push_back(v);
        } else if (c == ' ' || c == ',' || c == 'L') {  // 'L': Python 2 long suffix
            ++i;
        } else {
            throw Error(path, "malformed .npy header: bad 'shape' " + header.substr(p, e - p + 1));
        }
    }
    return fortran;
}

// Element size in bytes from a descr such as "<f4", "|u1", "<c16"; 0 if unknown.
std::size_t itemSize(const std::string& descr) {
    std::size_t i = 0;
    if (i < descr.size() && (descr[i] == '<' || descr[i] == '>' || descr[i] == '|' || descr[i] == '=')) ++i;
    if (i >= descr.size() || descr[i] == '\0' || std::strchr("biufcSUV", descr[i]) == nullptr) return 0;
    const char kind = descr[i++];
    if (i >= descr.size()) return 0;
    std::size_t n = 0;
    for (; i < descr.size(); ++i) {
        if (descr[i] < '0' || descr[i] > '9') return 0;
        n = n * 10 + std::size_t(descr[i] - '0');
    }
    if (kind == 'U') n *= 4;  // UCS-4 characters
    return n;
}

}  // namespace

template <>
std::string npyDescr<std::uint8_t>() {
    return "|u1";
}
template <>
std::string npyDescr<std::int8_t>() {
    return "|i1";
}
template <>
std::string npyDescr<std::uint16_t>() {
    return "<u2";
}
template <>
std::string npyDescr<std::int16_t>() {
    return "<i2";
}
template <>
std::string npyDescr<std::uint32_t>() {
    return "<u4";
}
template <>
std::string npyDescr<std::int32_t>() {
    return "<i4";
}
template <>
std::string npyDescr<std::uint64_t>() {
    return "<u8";
}
template <>
std::string npyDescr<std::int64_t>() {
    return "<i8";
}
template <>
std::string npyDescr<float>() {
    return "<f4";
}
template <>
std::string npyDescr<double>() {
    return "<f8";
}

void writeFileAtomic(const std::string& path, const std::function<void(std::ostream&)>& write) {
    const std::string tmp = path + ".tmp";
    int err = 0;
    try {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) throwErrno(path, errno);
        write(out);
        out.flush();
        if (!out) err = errno ? errno : EIO;
    } catch (...) {
        std::remove(tmp.c_str());
        throw;
    }
    if (!err) {  // to disk through a descriptor of its own: a stream shows none
        const int fd = ::open(tmp.c_str(), O_RDONLY);
        if (fd < 0) err = errno;
        if (fd >= 0 && ::fsync(fd) != 0) err = errno;
        if (fd >= 0) ::close(fd);
    }
    if (!err && std::rename(tmp.c_str(), path.c_str()) != 0) err = errno;
    if (err) {
        std::remove(tmp.c_str());
        throwErrno(path, err);
    }
}

void writeFileAtomic(const std::string& path, const void* data, std::size_t size) {
    writeFileAtomic(path, [&](std::ostream& os) { os.write(static_cast<const char*>(data), std::streamsize(size)); });
}

template <class T>
void writeNpy(const std::string& path, const T* data, const std::vector<std::size_t>& shape) {
    const std::size_t n = product(shape);
    if (n > 0 && data == nullptr) throw Error(path, "cannot write: no data for shape " + shapeText(shape));

    std::string dict =
        "{'descr': '" + npyDescr<T>() + "', 'fortran_order': False, 'shape': " + shapeText(shape) + ", }";
    const std::size_t preamble = kMagicSize + 2 + 2;  // magic, version, uint16 header length
    std::size_t total = preamble + dict.size() + 1;   // + '\n'
    total = (total + kAlign - 1) / kAlign * kAlign;
    const std::size_t headerLen = total - preamble;
    if (headerLen > std::numeric_limits<std::uint16_t>::max())
        throw Error(path, "cannot write: header too long for .npy version 1.0");
    dict.resize(headerLen - 1, ' ');
    dict += '\n';

    std::vector<unsigned char> file(total + n * sizeof(T));
    std::memcpy(file.data(), kMagic, kMagicSize);
    file[6] = 1;  // major version
    file[7] = 0;  // minor version
    file[8] = static_cast<unsigned char>(headerLen & 0xff);
    file[9] = static_cast<unsigned char>(headerLen >> 8);
    std::memcpy(file.data() + preamble, dict.data(), dict.size());
    if (n > 0) std::memcpy(file.data() + total, data, n * sizeof(T));
    writeFileAtomic(path, file.data(), file.size());
}

template void writeNpy(const std::string&, const std::uint8_t*, const std::vector<std::size_t>&);
template void writeNpy(const std::string&, const std::int8_t*, const std::vector<std::size_t>&);
template void writeNpy(const std::string&, const std::uint16_t*, const std::vector<std::size_t>&);
template void writeNpy(const std::string&, const std::int16_t*, const std::vector<std::size_t>&);
template void writeNpy(const std::string&, const std::uint32_t*, const std::vector<std::size_t>&);
template void writeNpy(const std::string&, const std::int32_t*, const std::vector<std::size_t>&);
template void writeNpy(const std::string&, const std::uint64_t*, const std::vector<std::size_t>&);
template void writeNpy(const std::string&, const std::int64_t*, const std::vector<std::size_t>&);
template void writeNpy(const std::string&, const float*, const std::vector<std::size_t>&);
template void writeNpy(const std::string&, const double*, const std::vector<std::size_t>&);

std::size_t NpyArray::count() const {
    return product(shape);
}

NpyArray readNpy(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path, std::string("cannot read: ") + std::strerror(errno));
    const std::vector<unsigned char> file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw Error(path, "cannot read: I/O error");

    if (file.size() < kMagicSize + 2 || std::memcmp(file.data(), kMagic, kMagicSize) != 0)
        throw Error(path, "not a .npy file (bad magic)");
    const int major = file[6], minor = file[7];
    if (major < 1 || major > 3)
        throw Error(path, "unsupported .npy version " + std::to_string(major) + "." + std::to_string(minor) +
                              " (expected 1.0, 2.0 or 3.0)");
    const std::size_t lenBytes = major == 1 ? 2 : 4;
    const std::size_t preamble = kMagicSize + 2 + lenBytes;
    if (file.size() < preamble) throw Error(path, "truncated .npy header");
    std::size_t headerLen = 0;
    for (std::size_t i = 0; i < lenBytes; ++i) headerLen |= std::size_t(file[8 + i]) << (8 * i);
    if (file.size() < preamble + headerLen) throw Error(path, "truncated .npy header");
    const std::string header(reinterpret_cast<const char*>(file.data() + preamble), headerLen);

    NpyArray out;
    if (parseHeader(path, header, out))
        throw Error(path, "Fortran-order arrays are unsupported (expected fortran_order False)");
    const std::size_t item = itemSize(out.descr);
    if (item == 0) throw Error(path, "unsupported dtype '" + out.descr + "'");

    const std::size_t want = out.count() * item;
    const std::size_t have = file.size() - preamble - headerLen;
    if (have < want)
        throw Error(path, "truncated data: expected " + std::to_string(want) + " bytes, found " + std::to_string(have));
    const auto* begin = file.data() + preamble + headerLen;
    out.bytes.assign(begin, begin + want);
    return out;
}

}  // namespace bop
