#include "KeyframeTestScene.hpp"

#include "TestUtil.hpp"
#include "shape/ScalarImage.hpp"

#include <sstream>

namespace bop::test {

const char* const kGrowFromSeeds = R"(
[[construction.event]]
step = 0
action = "seed"
species = 1
[[construction.event]]
step = 0
action = "birth_on"
species = 1
[[construction.event]]
step = 0
action = "seed"
species = 2
[[construction.event]]
step = 0
action = "birth_on"
species = 2
)";

std::string writeKeyframeScene(const std::string& dir, double frameDuration, bool blend, const std::string& extra) {
    std::vector<shape::ScalarImage> frames;
    for (double radius : {6.0, 9.0}) {
        shape::ScalarImage img;
        img.dims = Dims{24, 24, 24};
        img.spacingMm = Eigen::Vector3d::Ones();
        img.originMm = Eigen::Vector3d::Zero();
        img.values.assign(img.dims.count(), 0.0f);
        for (int z = 0; z < 24; ++z)
            for (int y = 0; y < 24; ++y)
                for (int x = 0; x < 24; ++x)
                    if ((Eigen::Vector3d(x, y, z).array() + 0.5 - 12).matrix().norm() <= radius)
                        img.values[img.dims.index(x, y, z)] = 1;
        frames.push_back(std::move(img));
    }
    shape::writeNifti4d(dir + "/ball.nii", frames, "uint8");
    std::ostringstream s;
    s << "[grid]\nr0_voxels = 2.0\nsize_voxels = [24, 24, 24]\n[shape]\n[[shape.bag]]\nsource = 'nifti'\nfile = "
         "'ball.nii'\n"
      << "label = 1\n"
      // Without a timeline of its own the bag starts empty (a scene with none is otherwise placed).
      << (extra.find("[construction]") == std::string::npos ? "[construction]\nmethod = 'birth'\n" : "")
      << "[keyframes]\nframe_duration = " << frameDuration << "\nblend = " << (blend ? "true" : "false") << "\n"
      << extra;
    return writeText(dir + "/keyframes.toml", s.str());
}

}  // namespace bop::test
