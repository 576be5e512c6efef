// OpenIGTLink's wire format as bop-igtl reads it (protocol/igtl/IgtlWire.hpp) against the
// reference library (Debian's libopenigtlink): the same CRC-64, messages the library packs read
// back to the same values, messages we encode accepted by the library's own checks; and each rule
// of a header or body broken once, refused with its reason; a header version 2 (protocol 3) body.
#include "igtl/IgtlMessages.hpp"
#include "igtl/IgtlWire.hpp"

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <igtlMessageHeader.h>
#include <igtlPolyDataMessage.h>
#include <igtlTransformMessage.h>
#include <igtl_util.h>

#include <limits>
#include <random>

using namespace bop::igtl;

namespace {

Header headerOf(const Bytes& msg, std::string& error, bool& ok) {
    Header h;
    ok = readHeader(std::span<const std::uint8_t, kHeaderSize>(msg.data(), kHeaderSize), h, error);
    return h;
}

// Why readTransform refuses the content of a whole message whose header and CRC are sound ("" if
// it reads it).
std::string transformRefusal(const Bytes& msg) {
    std::string error;
    bool ok = false;
    const Header h = headerOf(msg, error, ok);
    REQUIRE(ok);
    std::span<const std::uint8_t> content;
    REQUIRE(readContent(h, std::span(msg).subspan(kHeaderSize), content, error));
    Eigen::Matrix4d t;
    return readTransform(content, t, error) ? "" : error;
}

}  // namespace

TEST_CASE("igtl wire: CRC-64 is the reference library's", "[protocol][igtl]") {
    std::mt19937 rng(3);
    for (std::size_t n : {0, 1, 7, 48, 1000, 65537}) {
        std::vector<std::uint8_t> data(n);
        for (auto& b : data) b = std::uint8_t(rng());
        CHECK(crc64(data) == ::crc64(data.data(), n, 0));
    }
}

TEST_CASE("igtl wire: a TRANSFORM the library packs reads back to its matrix", "[protocol][igtl]") {
    Eigen::Matrix4d t = Eigen::Matrix4d::Identity();
    t.topLeftCorner<3, 3>() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    t.block<3, 1>(0, 3) = Eigen::Vector3d(12.5, -3.25, 100.0);
    const Bytes msg = transform("StylusTipToReference", t);
    std::string error;
    bool ok = false;
    const Header h = headerOf(msg, error, ok);
    REQUIRE(ok);
    CHECK(h.type == "TRANSFORM");
    CHECK(h.device == "StylusTipToReference");
    CHECK(h.bodySize == 48);
    std::span<const std::uint8_t> content;
    REQUIRE(readContent(h, std::span(msg).subspan(kHeaderSize), content, error));
    Eigen::Matrix4d back;
    REQUIRE(readTransform(content, back, error));
    CHECK((back - t).cwiseAbs().maxCoeff() < 1e-5);  // float32 on the wire
}

TEST_CASE("igtl wire: what we encode passes the library's own checks", "[protocol][igtl]") {
    Eigen::Matrix4d t = Eigen::Matrix4d::Identity();
    t(0, 3) = 4, t(1, 3) = 5, t(2, 3) = 6;
    const std::vector<std::uint8_t> body = transformBody(t);
    const Bytes msg = encodeMessage("TRANSFORM", "Tool", body);
    igtl::MessageHeader::Pointer header = igtl::MessageHeader::New();
    header->InitPack();
    std::copy(msg.begin(), msg.begin() + kHeaderSize, static_cast<std::uint8_t*>(header->GetPackPointer()));
    header->Unpack();
    CHECK(std::string(header->GetDeviceType()) == "TRANSFORM");
    CHECK(std::string(header->GetDeviceName()) == "Tool");
    igtl::TransformMessage::Pointer m = igtl::TransformMessage::New();
    m->SetMessageHeader(header);
    m->AllocatePack();
    std::copy(msg.begin() + kHeaderSize, msg.end(), static_cast<std::uint8_t*>(m->GetPackBodyPointer()));
    const int unpacked = m->Unpack(1);  // 1: check the CRC
    CHECK((unpacked & igtl::MessageHeader::UNPACK_BODY) != 0);
    igtl::Matrix4x4 mat;
    m->GetMatrix(mat);
    CHECK(mat[0][3] == 4.0f);
    CHECK(mat[1][3] == 5.0f);
    CHECK(mat[2][3] == 6.0f);
}

TEST_CASE("igtl wire: headers and bodies that break a rule are refused with the reason", "[protocol][igtl]") {
    const std::vector<std::uint8_t> body = transformBody(Eigen::Matrix4d::Identity());
    std::string error;
    bool ok = true;
    {
        Bytes msg = encodeMessage("TRANSFORM", "Tool", body);
        msg[1] = 99;  // version 99
        headerOf(msg, error, ok);
        CHECK(!ok);
        CHECK(error == "header version 99, expected 1 or 2");
    }
    {
        Bytes msg = encodeMessage("TRANSFORM", "Tool", body);
        msg[5] = 0x07;  // a control character in the type
        headerOf(msg, error, ok);
        CHECK(!ok);
        CHECK(error.find("message type is not printable ASCII") != std::string::npos);
    }
    {
        Bytes msg = encodeMessage("TRANSFORM", "Tool", body);
        msg[2 + kTypeSize + 6] = 'x';  // a character after the name's NUL
        headerOf(msg, error, ok);
        CHECK(!ok);
        CHECK(error.find("device name of a TRANSFORM") != std::string::npos);
    }
    {
        Bytes msg = encodeMessage("TRANSFORM", "Tool", body);
        for (int k = 0; k < 8; ++k) msg[42 + std::size_t(k)] = 0xff;  // 2^64 - 1 bytes of body
        headerOf(msg, error, ok);
        CHECK(!ok);
        CHECK(error.find("announces a body of 18446744073709551615 bytes") != std::string::npos);
    }
    {
        Bytes msg = encodeMessage("TRANSFORM", "Tool", body);
        msg.back() ^= 1;  // the body changed after its CRC was taken
        const Header h = headerOf(msg, error, ok);
        REQUIRE(ok);
        std::span<const std::uint8_t> content;
        CHECK(!readContent(h, std::span(msg).subspan(kHeaderSize), content, error));
        CHECK(error == "TRANSFORM 'Tool': body CRC-64 does not match the header's");
    }
    {
        const std::vector<std::uint8_t> short_(body.begin(), body.begin() + 40);
        CHECK(transformRefusal(encodeMessage("TRANSFORM", "Tool", short_)) ==
              "TRANSFORM content of 40 bytes, expected 48 (12 float32)");
    }
    {
        Eigen::Matrix4d nan = Eigen::Matrix4d::Identity();
        nan(1, 3) = std::numeric_limits<double>::quiet_NaN();
        CHECK(transformRefusal(encodeMessage("TRANSFORM", "Tool", transformBody(nan))) ==
              "TRANSFORM value 11 of 12 is not a finite number");
    }
}

TEST_CASE("igtl wire: a header version 2 body gives its content between extended header and metadata",
          "[protocol][igtl]") {
    const std::vector<std::uint8_t> content = transformBody(Eigen::Matrix4d::Identity());
    std::vector<std::uint8_t> body = {0, 12, 0, 0, 0, 0, 0, 5, 0, 0, 0, 1};  // 12-byte ext. header, 5 of metadata
    body.insert(body.end(), content.begin(), content.end());
    for (int k = 0; k < 5; ++k) body.push_back(std::uint8_t('a' + k));
    Bytes msg = encodeMessage("TRANSFORM", "Tool", body, 2);
    std::string error;
    bool ok = false;
    const Header h = headerOf(msg, error, ok);
    REQUIRE(ok);
    std::span<const std::uint8_t> got;
    REQUIRE(readContent(h, std::span(msg).subspan(kHeaderSize), got, error));
    CHECK(std::vector<std::uint8_t>(got.begin(), got.end()) == content);
    body[7] = 200;  // metadata larger than the body
    msg = encodeMessage("TRANSFORM", "Tool", body, 2);
    const Header h2 = headerOf(msg, error, ok);
    CHECK(!readContent(h2, std::span(msg).subspan(kHeaderSize), got, error));
    CHECK(error.find("do not fit its body") != std::string::npos);
}

TEST_CASE("igtl wire: the POLYDATA we pack, the library unpacks to the same points and point data",
          "[protocol][igtl]") {
    PointSet set;
    for (int k = 0; k < 5; ++k) {
        set.points.emplace_back(float(k), float(2 * k) - 0.5f, 100.25f);
        set.normals.push_back(Eigen::Vector3f(float(k), 1, 0).normalized());
        set.species.push_back(float(1 + k % 2));
    }
    const Bytes msg = polyData("BoP surface", set);
    igtl::MessageHeader::Pointer header = igtl::MessageHeader::New();
    header->InitPack();
    std::copy(msg.begin(), msg.begin() + kHeaderSize, static_cast<std::uint8_t*>(header->GetPackPointer()));
    header->Unpack();
    REQUIRE(std::string(header->GetDeviceType()) == "POLYDATA");
    igtl::PolyDataMessage::Pointer m = igtl::PolyDataMessage::New();
    m->SetMessageHeader(header);
    m->AllocatePack();
    std::copy(msg.begin() + kHeaderSize, msg.end(), static_cast<std::uint8_t*>(m->GetPackBodyPointer()));
    REQUIRE((m->Unpack(1) & igtl::MessageHeader::UNPACK_BODY) != 0);  // CRC checked
    REQUIRE(m->GetPoints()->GetNumberOfPoints() == 5);
    CHECK(m->GetVertices()->GetNumberOfCells() == 5);
    for (int k = 0; k < 5; ++k) {
        igtlFloat32 p[3];
        m->GetPoints()->GetPoint(unsigned(k), p);
        CHECK(Eigen::Vector3f(p[0], p[1], p[2]) == set.points[std::size_t(k)]);
    }
    REQUIRE(m->GetNumberOfAttributes() == 2);
    CHECK(std::string(m->GetAttribute(0)->GetName()) == "Normals");
    CHECK(m->GetAttribute(0)->GetType() == igtl::PolyDataAttribute::POINT_NORMAL);
    CHECK(std::string(m->GetAttribute(1)->GetName()) == "Species");
    igtlFloat32 normal[3], species[1];
    m->GetAttribute(0)->GetNthData(3, normal);
    m->GetAttribute(1)->GetNthData(3, species);
    CHECK(Eigen::Vector3f(normal[0], normal[1], normal[2]) == set.normals[3]);
    CHECK(species[0] == set.species[3]);
    const Bytes l = line("ProbeForce", {0, 0, 0}, {1, 2, 3});  // one line cell of two points
    std::span<const std::uint8_t> content;
    std::string error;
    bool ok = false;
    const Header h = headerOf(l, error, ok);
    REQUIRE(ok);
    REQUIRE(readContent(h, std::span(l).subspan(kHeaderSize), content, error));
    CHECK(content.size() == 40 + 24 + 12);  // counts, two points, one cell (count and two indices)
}
