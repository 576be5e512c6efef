#include "IgtlMessages.hpp"

#include "IgtlWire.hpp"

#include <igtlImageMessage.h>
#include <igtlTransformMessage.h>

#include <chrono>
#include <cstring>
#include <stdexcept>

namespace bop::igtl {
namespace {

Bytes packed(::igtl::MessageBase* m) {
    m->Pack();
    const auto* p = static_cast<const std::uint8_t*>(m->GetPackPointer());
    return Bytes(p, p + m->GetPackSize());
}

// OpenIGTLink's time stamp: seconds since 1970 in the high 32 bits, the fraction of a second in the low.
std::uint64_t timestampNow() {
    const auto ns =
        std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
            .count();
    const std::uint64_t sec = std::uint64_t(ns / 1000000000), frac = std::uint64_t(ns % 1000000000);
    return sec << 32 | ((frac << 32) / 1000000000);
}

void stamp(::igtl::MessageBase* m, const std::string& device) {
    if (device.size() > 20) throw std::invalid_argument("OpenIGTLink device name '" + device + "' is longer than 20");
    m->SetDeviceName(device.c_str());
    ::igtl::TimeStamp::Pointer ts = ::igtl::TimeStamp::New();
    ts->GetTime();
    m->SetTimeStamp(ts);
}

// POLYDATA packed here from the specification's layout rather than by the library, whose cell
// arrays hold a list per cell (an allocation per particle) and whose CRC-64 goes bit by bit:
// with them bop-igtl spent 60% of its time there and a 12,000-particle bag reached 31 updates/s
// of 60 asked. The library reads what this writes (tests/protocol/TestIgtlWire.cpp).
class BigEndian {
public:
    explicit BigEndian(std::size_t bytes) { out_.reserve(bytes); }
    void u8(std::uint8_t v) { out_.push_back(v); }
    void u32(std::uint32_t v) {
        for (int k = 3; k >= 0; --k) out_.push_back(std::uint8_t(v >> (8 * k)));
    }
    void f32(float v) {
        std::uint32_t bits;
        std::memcpy(&bits, &v, sizeof bits);
        u32(bits);
    }
    void text(const std::string& s) {
        out_.insert(out_.end(), s.begin(), s.end());
        out_.push_back(0);
    }
    Bytes& bytes() { return out_; }

private:
    Bytes out_;
};

struct Attribute {
    std::uint8_t type, components;  // the specification's TYPE_ATTRIBUTE (0: point scalars, 2: point normals)
    std::string name;
    const float* data;  // components values per point
};

// cells: each a list of point indices, written as the vertex cells (`lines` false) or line cells.
Bytes polyDataOf(const std::string& device, const std::vector<Eigen::Vector3f>& points,
                 const std::vector<std::vector<std::uint32_t>>* cells, bool lines,
                 const std::vector<Attribute>& attributes) {
    const std::size_t n = points.size();
    const bool vertices = cells == nullptr;  // one vertex cell per point
    std::size_t cellBytes = vertices ? 8 * n : 0;
    if (cells)
        for (const auto& c : *cells) cellBytes += 4 * (c.size() + 1);
    std::size_t names = 0, values = 0;
    for (const Attribute& at : attributes) names += at.name.size() + 1, values += n * at.components;
    names += names % 2;  // the name table's length is even
    BigEndian w(40 + 12 * n + cellBytes + 6 * attributes.size() + names + 4 * values);
    w.u32(std::uint32_t(n));
    const std::uint32_t nCells = vertices ? std::uint32_t(n) : std::uint32_t(cells->size());
    w.u32(lines ? 0 : nCells), w.u32(lines ? 0 : std::uint32_t(cellBytes));
    w.u32(lines ? nCells : 0), w.u32(lines ? std::uint32_t(cellBytes) : 0);
    for (int k = 0; k < 4; ++k) w.u32(0);  // no polygons, no triangle strips
    w.u32(std::uint32_t(attributes.size()));
    for (const Eigen::Vector3f& p : points) w.f32(p.x()), w.f32(p.y()), w.f32(p.z());
    if (vertices) {
        for (std::size_t k = 0; k < n; ++k) w.u32(1), w.u32(std::uint32_t(k));
    } else {
        for (const auto& c : *cells) {
            w.u32(std::uint32_t(c.size()));
            for (std::uint32_t i : c) w.u32(i);
        }
    }
    for (const Attribute& at : attributes) w.u8(at.type), w.u8(at.components), w.u32(std::uint32_t(n));
    std::size_t written = 0;
    for (const Attribute& at : attributes) w.text(at.name), written += at.name.size() + 1;
    if (written % 2) w.u8(0);
    for (const Attribute& at : attributes)
        for (std::size_t k = 0; k < n * at.components; ++k) w.f32(at.data[k]);
    return encodeMessage("POLYDATA", device, w.bytes(), 1, timestampNow());
}

}  // namespace

Bytes polyData(const std::string& device, const PointSet& set) {
    const std::size_t n = set.points.size();
    std::vector<Attribute> attributes;
    if (n > 0 && set.normals.size() == n) attributes.push_back({2, 3, "Normals", set.normals[0].data()});
    if (n > 0 && set.species.size() == n) attributes.push_back({0, 1, "Species", set.species.data()});
    return polyDataOf(device, set.points, nullptr, false, attributes);
}

Bytes line(const std::string& device, const Eigen::Vector3f& from, const Eigen::Vector3f& to) {
    const std::vector<std::vector<std::uint32_t>> cells = {{0, 1}};
    return polyDataOf(device, {from, to}, &cells, true, {});
}

Bytes transform(const std::string& device, const Eigen::Matrix4d& t) {
    ::igtl::TransformMessage::Pointer m = ::igtl::TransformMessage::New();
    stamp(m, device);
    ::igtl::Matrix4x4 mat;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) mat[r][c] = float(t(r, c));
    m->SetMatrix(mat);
    return packed(m);
}

Bytes labelImage(const std::string& device, const LabelImage& image) {
    const std::size_t count = std::size_t(image.dims[0]) * std::size_t(image.dims[1]) * std::size_t(image.dims[2]);
    if (image.labels.size() != count)
        throw std::invalid_argument("label image of " + std::to_string(image.labels.size()) + " values, dims give " +
                                    std::to_string(count));
    ::igtl::ImageMessage::Pointer m = ::igtl::ImageMessage::New();
    stamp(m, device);
    int dims[3] = {image.dims[0], image.dims[1], image.dims[2]};
    m->SetDimensions(dims);
    m->SetScalarTypeToUint8();
    m->SetCoordinateSystem(::igtl::ImageMessage::COORDINATE_RAS);
    ::igtl::Matrix4x4 mat;
    ::igtl::IdentityMatrix(mat);
    const Eigen::Vector4d centre =
        image.ijkToRas * Eigen::Vector4d(0.5 * (dims[0] - 1), 0.5 * (dims[1] - 1), 0.5 * (dims[2] - 1), 1.0);
    float spacing[3];
    for (int c = 0; c < 3; ++c) {
        const Eigen::Vector3d axis = image.ijkToRas.block<3, 1>(0, c);
        spacing[c] = float(axis.norm());
        for (int r = 0; r < 3; ++r) mat[r][c] = float(axis[r] / axis.norm());
        mat[c][3] = float(centre[c]);
    }
    m->SetMatrix(mat);
    m->SetSpacing(spacing);
    m->AllocateScalars();
    std::copy(image.labels.begin(), image.labels.end(), static_cast<std::uint8_t*>(m->GetScalarPointer()));
    return packed(m);
}

}  // namespace bop::igtl
