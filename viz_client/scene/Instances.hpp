#pragma once
// The viewer's GL-free stage (docs/viewer.md): a state frame and the scene info become the arrays
// the renderer draws with one instanced call per kind — oriented discs (surfels) for surface
// particles, sphere impostors for volume particles — after the view's filters: kinds and species
// shown, and a cut plane that removes what lies in front of it. No OpenGL here, so it is tested
// on its own.
#include "codec/Messages.hpp"

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace bop::viz {

// Disc radius of a surface particle, in r0. Surface particles sit about r0 apart (the LJ
// minimum); discs of radius R cover a triangulated sheet without holes when R is at least the
// circumradius of its triangles, r0 / sqrt 3 = 0.577 r0 for equilateral ones. A bag as the
// server builds it is looser: in the recorded torus (tests/viz/data) discs of 0.76 r0 let the
// fill show through 1.6% of the bag's pixels, 0.9 r0 only 0.1%. 0.9 r0 covers equilateral
// triangles stretched to 1.56 r0 per edge.
inline constexpr double kSurfelRadiusR0 = 0.9;
// Sphere radius of a volume particle, in r0: neighbours at r0 touch.
inline constexpr double kSphereRadiusR0 = 0.5;
// Colour of particles whose species the scene info does not list (straight RGBA).
inline constexpr std::array<std::uint8_t, 4> kUnknownSpeciesRgba{128, 128, 128, 255};

struct Surfel {
    float position[3];   // centre, length
    float normal[3];     // unit
    float radius;        // length
    std::uint32_t rgba;  // straight alpha; red in the lowest byte (GL_UNSIGNED_BYTE x 4)
};

struct Sphere {
    float position[3];   // centre, length
    float radius;        // length
    std::uint32_t rgba;  // as Surfel::rgba
};

// Keeps the half space (x - point) . normal <= 0: particles in front of the plane (on the side
// its normal points to) are removed, so the interior shows.
struct CutPlane {
    Eigen::Vector3d point = Eigen::Vector3d::Zero();    // length
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // any length > 0
};

struct ViewFilter {
    bool showSurface = true;
    bool showVolume = true;
    std::vector<bool> hiddenSpecies;  // by species number (index 0 unused); beyond its end: shown
    std::optional<CutPlane> cut;
    double surfelRadiusR0 = kSurfelRadiusR0;  // disc radius, r0
    double sphereRadiusR0 = kSphereRadiusR0;  // sphere radius, r0
};

struct Instances {
    std::vector<Surfel> surfels;
    std::vector<Sphere> spheres;
    std::size_t cut = 0;                       // particles removed by the cut plane
    std::size_t hidden = 0;                    // particles of a kind or species not shown
    std::size_t unknownSpecies = 0;            // drawn grey as spheres: their species is not in the scene info
    std::vector<std::size_t> drawnPerSpecies;  // by species number (index 0 unused)
};

// The probe as drawn: a small opaque core at its centre and a translucent sphere of its reach
// (the distance within which it acts on particles: SceneInfo::probeReach times k0).
struct ProbeMarker {
    Sphere core;   // radius 0.3 r0
    Sphere reach;  // alpha 0.25
};
ProbeMarker probeMarker(const Eigen::Vector3d& position, double reach, double r0, bool active);

// Straight RGBA bytes as one value, red in the lowest byte.
std::uint32_t packRgba(const std::array<std::uint8_t, 4>& rgba);

// Fills `out` from frame `f` as scene `s` describes its species, reusing out's memory. A frame
// without normals draws its surface particles as spheres (a disc needs a facing).
void buildInstances(const protocol::StateFrame& f, const protocol::SceneInfo& s, const ViewFilter& view,
                    Instances& out);

}  // namespace bop::viz
