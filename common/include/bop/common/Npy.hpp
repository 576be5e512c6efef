#pragma once
// NumPy .npy files (format version 1.0 written; 1.0, 2.0 and 3.0 read).
// Arrays are C order (last index fastest), little-endian. A Volume's per-voxel
// array (x fastest) is therefore written with shape {nz, ny, nx}.
// Errors are bop::Error(path, what).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace bop {

// NumPy dtype string of T, e.g. "<f4" for float, "|u1" for uint8_t.
// Defined for uint8_t, int8_t, uint16_t, int16_t, uint32_t, int32_t, uint64_t,
// int64_t, float and double.
template <class T>
std::string npyDescr();

// Writes data (product of shape elements, C order) to path as .npy version 1.0.
// The header is padded with spaces and ends with '\n' so that the data starts at a
// multiple of 64 bytes. An empty shape writes a 0-d array of one element.
// Atomic: writes path + ".tmp", flushes it to disk and renames it over path, so
// path holds either its previous content or the complete new file.
template <class T>
void writeNpy(const std::string& path, const T* data, const std::vector<std::size_t>& shape);

struct NpyArray {
    std::string descr;                 // NumPy dtype string as in the file, e.g. "<i2"
    std::vector<std::size_t> shape;    // C order; empty for a 0-d array
    std::vector<unsigned char> bytes;  // raw element bytes, count() * itemsize

    // Number of elements: product of shape (1 for a 0-d array).
    std::size_t count() const;
};

// Reads a .npy file. Fails (bop::Error(path, ...)) on a missing or unreadable file,
// bad magic, unsupported version, malformed header, Fortran order, an object or
// unknown dtype, or data shorter than the header promises. Trailing bytes are ignored.
NpyArray readNpy(const std::string& path);

// Writes size bytes to path atomically (path + ".tmp", fsync, rename).
// Throws bop::Error(path, "cannot write: <strerror>"). Shared by writeNpy and Canvas.
void writeFileAtomic(const std::string& path, const void* data, std::size_t size);
// The same for text written to a stream as it is made (a state of 10^6 particles is 184 MB of
// text, better not held twice in memory): `write` fills the stream of path + ".tmp".
void writeFileAtomic(const std::string& path, const std::function<void(std::ostream&)>& write);

}  // namespace bop
