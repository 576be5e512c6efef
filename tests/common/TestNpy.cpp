#include "TestUtil.hpp"
#include "bop/common/Error.hpp"
#include "bop/common/Npy.hpp"

#include <catch2/catch.hpp>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace fs = std::filesystem;

namespace {

// A fresh file path in the temporary directory, unique to this process.
std::string tempPath(const std::string& name) {
    static const bop::test::TempDir dir("npy");
    return dir.file(name);
}

template <class T>
std::vector<T> asValues(const bop::NpyArray& a) {
    std::vector<T> v(a.count());
    REQUIRE(a.bytes.size() == v.size() * sizeof(T));
    std::memcpy(v.data(), a.bytes.data(), a.bytes.size());
    return v;
}

std::size_t headerEnd(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    unsigned char pre[10] = {};
    in.read(reinterpret_cast<char*>(pre), 10);
    return 10 + std::size_t(pre[8]) + 256 * std::size_t(pre[9]);
}

// A python3 interpreter that can import numpy, or "" if none.
std::string pythonWithNumpy() {
    for (const char* py : {"python3", "/usr/bin/python3"}) {
        const std::string cmd = std::string(py) + " -c \"import numpy\" > /dev/null 2>&1";
        if (std::system(cmd.c_str()) == 0) return py;
    }
    return "";
}

}  // namespace

TEST_CASE("npy round trip of uint8", "[npy]") {
    const std::string path = tempPath("u8.npy");
    std::vector<std::uint8_t> data(17);
    for (std::size_t i = 0; i < data.size(); ++i) data[i] = std::uint8_t(i * 15);
    bop::writeNpy(path, data.data(), {data.size()});
    const bop::NpyArray a = bop::readNpy(path);
    CHECK(a.descr == "|u1");
    CHECK(a.shape == std::vector<std::size_t>{17});
    CHECK(asValues<std::uint8_t>(a) == data);
    CHECK_FALSE(fs::exists(path + ".tmp"));
}

TEST_CASE("npy round trip of int16 with shape (4, 3, 2, 3)", "[npy]") {
    const std::string path = tempPath("i16.npy");
    std::vector<std::int16_t> data(4 * 3 * 2 * 3);
    for (std::size_t i = 0; i < data.size(); ++i) data[i] = std::int16_t(int(i) * 997 - 30000);
    bop::writeNpy(path, data.data(), {4, 3, 2, 3});
    const bop::NpyArray a = bop::readNpy(path);
    CHECK(a.descr == "<i2");
    CHECK(a.shape == std::vector<std::size_t>{4, 3, 2, 3});
    CHECK(a.count() == data.size());
    CHECK(asValues<std::int16_t>(a) == data);
}

TEST_CASE("npy round trip of float, overwriting an existing file", "[npy]") {
    const std::string path = tempPath("f32.npy");
    const std::vector<float> first = {9.0f};
    bop::writeNpy(path, first.data(), {1});
    const std::vector<float> data = {0.0f, -1.5f, 3.25e-7f, 1e30f, 2.0f, 7.0f};
    bop::writeNpy(path, data.data(), {2, 3});
    const bop::NpyArray a = bop::readNpy(path);
    CHECK(a.descr == "<f4");
    CHECK(a.shape == std::vector<std::size_t>{2, 3});
    CHECK(asValues<float>(a) == data);
}

TEST_CASE("npy 0-d array and descr strings", "[npy]") {
    const std::string path = tempPath("scalar.npy");
    const double x = 2.5;
    bop::writeNpy(path, &x, {});
    const bop::NpyArray a = bop::readNpy(path);
    CHECK(a.descr == "<f8");
    CHECK(a.shape.empty());
    CHECK(asValues<double>(a) == std::vector<double>{2.5});
    CHECK(bop::npyDescr<std::int8_t>() == "|i1");
    CHECK(bop::npyDescr<std::uint16_t>() == "<u2");
    CHECK(bop::npyDescr<std::int32_t>() == "<i4");
    CHECK(bop::npyDescr<std::uint32_t>() == "<u4");
    CHECK(bop::npyDescr<std::int64_t>() == "<i8");
}

TEST_CASE("npy header ends with a newline at a multiple of 64 bytes", "[npy]") {
    // Shapes with a zero extent hold no data, so long headers cost nothing.
    const std::vector<std::vector<std::size_t>> shapes = {
        {},
        {1},
        {0, 123456789},
        {0, 1, 22, 333, 4444, 55555, 666666},
        {0, 100000000, 100000000, 100000000, 100000000, 100000000, 100000000}};
    for (const auto& shape : shapes) {
        const std::string path = tempPath("align.npy");
        const std::int32_t value = 42;
        bop::writeNpy(path, &value, shape);
        const std::size_t end = headerEnd(path);
        CHECK(end % 64 == 0);
        std::ifstream in(path, std::ios::binary);
        std::string file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        std::size_t count = 1;
        for (std::size_t d : shape) count *= d;
        REQUIRE(file.size() == end + count * sizeof value);
        CHECK(file[end - 1] == '\n');
        CHECK(file.compare(0, 8, std::string("\x93NUMPY\x01\x00", 8)) == 0);
        CHECK(bop::readNpy(path).shape == shape);
    }
}

TEST_CASE("readNpy rejects bad files with an Error naming the path", "[npy]") {
    const std::string path = tempPath("bad.npy");
    std::vector<std::int16_t> data(100, 7);
    bop::writeNpy(path, data.data(), {10, 10});
    const auto size = fs::file_size(path);

    SECTION("truncated data") {
        fs::resize_file(path, size - 1);
        CHECK_THROWS_WITH(bop::readNpy(path), Catch::Contains(path) && Catch::Contains("truncated"));
        try {
            bop::readNpy(path);
        } catch (const bop::Error& e) {
            CHECK(e.where() == path);
        }
    }
    SECTION("truncated header") {
        fs::resize_file(path, 30);
        CHECK_THROWS_AS(bop::readNpy(path), bop::Error);
    }
    SECTION("bad magic") {
        std::ofstream(path, std::ios::binary) << "not numpy at all";
        CHECK_THROWS_WITH(bop::readNpy(path), Catch::Contains(path) && Catch::Contains("magic"));
    }
    SECTION("unsupported version") {
        std::fstream f(path, std::ios::binary | std::ios::in | std::ios::out);
        f.seekp(6);
        f.put(char(9));
        f.close();
        CHECK_THROWS_WITH(bop::readNpy(path), Catch::Contains("version"));
    }
    SECTION("Fortran order") {
        std::fstream f(path, std::ios::binary | std::ios::in | std::ios::out);
        std::string head(64, '\0');
        f.read(head.data(), 64);
        const auto at = head.find("False");
        REQUIRE(at != std::string::npos);
        f.seekp(std::streamoff(at));
        f.write("True ", 5);
        f.close();
        CHECK_THROWS_WITH(bop::readNpy(path), Catch::Contains("Fortran"));
    }
    SECTION("missing file") {
        const std::string missing = tempPath("missing.npy");
        CHECK_THROWS_WITH(bop::readNpy(missing), Catch::Contains(missing));
    }
}

TEST_CASE("writeNpy reports an unwritable path", "[npy]") {
    const std::string path = tempPath("no_such_dir") + "/x.npy";
    const std::uint8_t b = 1;
    CHECK_THROWS_WITH(bop::writeNpy(path, &b, {1}), Catch::Contains(path) && Catch::Contains("cannot write"));
}

TEST_CASE("a file written atomically from a stream: whole when done, the old one kept on a failure", "[npy]") {
    const std::string path = tempPath("atomic_stream.txt");
    bop::writeFileAtomic(path, [](std::ostream& os) {
        for (int i = 0; i < 100000; ++i) os << i << '\n';  // about 0.6 MB, several buffers' worth
    });
    std::ifstream in(path);
    int n = 0, v = 0, bad = 0;
    while (in >> v) bad += v != n++;
    CHECK(n == 100000);
    CHECK(bad == 0);
    CHECK_FALSE(fs::exists(path + ".tmp"));
    // A writer that fails half-way: an error, no temporary left, the earlier file as it was.
    CHECK_THROWS_WITH(bop::writeFileAtomic(path,
                                           [](std::ostream& os) {
                                               os << "half";
                                               throw bop::Error("writer", "stopped");
                                           }),
                      Catch::Contains("stopped"));
    CHECK_FALSE(fs::exists(path + ".tmp"));
    std::ifstream again(path);
    int kept = 0;
    while (again >> v) ++kept;
    CHECK(kept == 100000);
    const std::string nowhere = tempPath("no_such_dir") + "/x.txt";
    CHECK_THROWS_WITH(bop::writeFileAtomic(nowhere, [](std::ostream& os) { os << 1; }),
                      Catch::Contains(nowhere) && Catch::Contains("cannot write"));
    fs::remove(path);
}

TEST_CASE("numpy.load reads what writeNpy wrote", "[npy][python]") {
    const std::string python = pythonWithNumpy();
    if (python.empty()) {
        WARN("python3 with numpy not available: skipping the numpy.load check");
        return;
    }
    const std::string path = tempPath("numpy_check.npy");
    const std::string outPath = tempPath("numpy_check.txt");
    std::vector<std::int16_t> data(4 * 3 * 2 * 3);
    long long sum = 0;
    for (std::size_t i = 0; i < data.size(); ++i) {
        data[i] = std::int16_t(int(i) * 731 - 20000);
        sum += data[i];
    }
    bop::writeNpy(path, data.data(), {4, 3, 2, 3});
    const std::string cmd = python +
                            " -c \"import numpy as np, sys; a = np.load(sys.argv[1]); "
                            "print(a.shape, a.dtype, int(a.astype(np.int64).sum()))\" '" +
                            path + "' > '" + outPath + "'";
    REQUIRE(std::system(cmd.c_str()) == 0);
    std::ifstream in(outPath);
    std::string line;
    std::getline(in, line);
    std::ostringstream expected;
    expected << "(4, 3, 2, 3) int16 " << sum;
    CHECK(line == expected.str());
}
