// A main() for a libFuzzer target built without libFuzzer (bop_front_replay: FuzzFront.cpp with
// GCC, in the normal build): runs the inputs named on the command line, each as it is and then
// --mutations times changed at random (bytes flipped, inserted, erased, copied from another
// input; a fixed --seed), so that CI runs the target's contract on its seeds and their neighbours
// without a fuzzing build. Exits 0 when every input ran; a broken contract aborts.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv);
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

using Bytes = std::vector<std::uint8_t>;

Bytes mutate(Bytes b, const std::vector<Bytes>& all, std::mt19937& rng) {
    for (int edits = 1 + int(rng() % 4); edits > 0; --edits) {
        const std::size_t at = b.empty() ? 0 : rng() % b.size();
        switch (rng() % 5) {
            case 0:
                if (!b.empty()) b[at] ^= std::uint8_t(1u << (rng() % 8));
                break;
            case 1:
                if (!b.empty()) b[at] = std::uint8_t(rng());
                break;
            case 2:
                b.insert(b.begin() + long(at), std::uint8_t(rng()));
                break;
            case 3:
                if (!b.empty()) b.erase(b.begin() + long(at), b.begin() + long(std::min(b.size(), at + 1 + rng() % 8)));
                break;
            default: {  // a piece of another input
                const Bytes& o = all[rng() % all.size()];
                if (o.empty()) break;
                const std::size_t from = rng() % o.size(), n = std::min<std::size_t>(o.size() - from, 1 + rng() % 64);
                b.insert(b.begin() + long(at), o.begin() + long(from), o.begin() + long(from + n));
            }
        }
    }
    return b;
}

}  // namespace

int main(int argc, char** argv) {
    int mutations = 0;
    unsigned seed = 1;
    std::vector<Bytes> inputs;
    for (int k = 1; k < argc; ++k) {
        if (!std::strcmp(argv[k], "--mutations") && k + 1 < argc) {
            mutations = std::atoi(argv[++k]);
        } else if (!std::strcmp(argv[k], "--seed") && k + 1 < argc) {
            seed = unsigned(std::atoi(argv[++k]));
        } else {
            std::ifstream in(argv[k], std::ios::binary);
            if (!in) {
                std::fprintf(stderr, "%s: cannot read %s\n", argv[0], argv[k]);
                return 2;
            }
            inputs.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
        }
    }
    if (inputs.empty()) {
        std::fprintf(stderr, "usage: %s [--mutations N] [--seed S] INPUT...\n", argv[0]);
        return 2;
    }
    LLVMFuzzerInitialize(&argc, &argv);
    std::mt19937 rng(seed);
    std::size_t runs = 0;
    for (const Bytes& in : inputs) {
        LLVMFuzzerTestOneInput(in.data(), in.size()), ++runs;
        for (int m = 0; m < mutations; ++m) {
            const Bytes b = mutate(in, inputs, rng);
            LLVMFuzzerTestOneInput(b.data(), b.size()), ++runs;
        }
    }
    std::printf("%s: %zu inputs ran, the contract held\n", argv[0], runs);
    return 0;
}
