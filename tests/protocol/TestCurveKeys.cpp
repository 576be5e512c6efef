// CURVE key files (security/CurveKeys.hpp): the pair bop-keys writes, and files that are not keys.
#include "TestUtil.hpp"
#include "bop/common/Error.hpp"
#include "security/CurveKeys.hpp"

#include <catch2/catch.hpp>
#include <zmq.h>

#include <array>
#include <filesystem>
#include <fstream>

using namespace bop::protocol;
namespace fs = std::filesystem;

namespace {

fs::perms permsOf(const std::string& path) {
    return fs::status(path).permissions() & fs::perms::all;
}

// Expects readCurveKey(path) to fail with an error that names the file and says `why`.
void expectRefused(const std::string& path, const std::string& why) {
    try {
        readCurveKey(path);
        FAIL("accepted " << path);
    } catch (const bop::Error& e) {
        CHECK(e.where() == path);
        CHECK_THAT(e.what(), Catch::Contains(why));
    }
}

}  // namespace

TEST_CASE("CURVE keys: a written pair reads back, the secret one private", "[protocol][client]") {
    bop::test::TempDir dir("curve-keys");
    const std::string prefix = dir.file("server");
    const CurveKeyPair keys = makeCurveKeyPair();
    writeCurveKeyFiles(prefix, keys);
    CHECK(permsOf(prefix + ".key") == (fs::perms::owner_read | fs::perms::owner_write));
    CHECK((permsOf(prefix + ".pub") & fs::perms::others_read) != fs::perms::none);
    const std::string secret = readCurveKey(prefix + ".key"), pub = readCurveKey(prefix + ".pub");
    CHECK(secret == keys.secretKey);
    CHECK(pub == keys.publicKey);
    std::array<char, 41> derived{};
    REQUIRE(zmq_curve_public(derived.data(), secret.c_str()) == 0);
    CHECK(std::string(derived.data()) == pub);

    // Existing keys are kept unless replacing is asked for; replacing narrows a wide mode.
    CHECK_THROWS_WITH(writeCurveKeyFiles(prefix, makeCurveKeyPair()), Catch::Contains("already exists"));
    CHECK(readCurveKey(prefix + ".key") == keys.secretKey);
    fs::permissions(prefix + ".key", fs::perms::owner_all | fs::perms::group_read | fs::perms::others_read);
    const CurveKeyPair other = makeCurveKeyPair();
    writeCurveKeyFiles(prefix, other, true);
    CHECK(readCurveKey(prefix + ".key") == other.secretKey);
    CHECK(permsOf(prefix + ".key") == (fs::perms::owner_read | fs::perms::owner_write));
    // A refusal writes neither file.
    bop::test::writeText(dir.file("half.pub"), other.publicKey + "\n");
    CHECK_THROWS_AS(writeCurveKeyFiles(dir.file("half"), other), bop::Error);
    CHECK_FALSE(fs::exists(dir.file("half.key")));
    CHECK_THROWS_WITH(writeCurveKeyFiles(dir.file("no/such/folder/x"), other), Catch::Contains("cannot create"));
}

TEST_CASE("CURVE keys: files that are not one z85 key are refused, naming the file", "[protocol][client]") {
    bop::test::TempDir dir("curve-bad");
    const std::string key = makeCurveKeyPair().publicKey;
    CHECK(readCurveKey(bop::test::writeText(dir.file("lf.pub"), key + "\n")) == key);
    CHECK(readCurveKey(bop::test::writeText(dir.file("crlf.pub"), key + "\r\n")) == key);
    CHECK(readCurveKey(bop::test::writeText(dir.file("bare.pub"), key)) == key);

    expectRefused(dir.file("missing.pub"), "cannot read");
    expectRefused(dir.path.string(), "is a folder");
    expectRefused(bop::test::writeText(dir.file("empty.pub"), ""), "0 characters");
    expectRefused(bop::test::writeText(dir.file("short.pub"), key.substr(1) + "\n"), "39 characters");
    expectRefused(bop::test::writeText(dir.file("long.pub"), key + "x\n"), "41 characters");
    expectRefused(bop::test::writeText(dir.file("two.pub"), key + "\n" + key + "\n"), "81 characters");
    expectRefused(bop::test::writeText(dir.file("blank.pub"), key + "\n\n"), "41 characters");
    expectRefused(bop::test::writeText(dir.file("space.pub"), " " + key.substr(1)), "not a z85 CURVE key");
    expectRefused(bop::test::writeText(dir.file("quote.pub"), "\"" + key.substr(1)), "not a z85 CURVE key");
    expectRefused(bop::test::writeText(dir.file("big.pub"), std::string(100000, 'a')), "more than 256 bytes");

    CHECK(isCurveKey(key));
    CHECK_FALSE(isCurveKey(key.substr(0, 39)));
    CHECK_FALSE(isCurveKey(std::string(40, '~')));
}
