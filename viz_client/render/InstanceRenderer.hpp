#pragma once
// Draws the viewer's instance arrays (scene/Instances.hpp) with OpenGL 3.3 core: one instanced
// call for the surfels (a quad per particle turned to face its normal, cut to a disc in the
// fragment shader) and one for the volume particles (sphere impostors: a camera-facing quad per
// particle, the sphere ray-traced per fragment with its true depth). Lighting is a headlight
// (light from the eye): ambient 0.35, diffuse 0.65. Needs a current context (EglHeadless or a
// window's).
#include "scene/Camera.hpp"
#include "scene/Instances.hpp"

#include <array>

namespace bop::viz {

class InstanceRenderer {
public:
    InstanceRenderer();  // compiles the shaders; bop::Error with the compiler's log on failure
    ~InstanceRenderer();
    InstanceRenderer(const InstanceRenderer&) = delete;
    InstanceRenderer& operator=(const InstanceRenderer&) = delete;

    // Clears the bound framebuffer to `background` (RGB 0..1) and draws the instances as seen
    // by the camera in a viewport of width x height pixels.
    void draw(const Instances& instances, const OrbitCamera& camera, int width, int height,
              const std::array<float, 3>& background);
    // Draws translucent spheres (their colours' alpha) over what is drawn, blended, without
    // hiding what lies behind them: the probe's reach.
    void drawTranslucent(const std::vector<Sphere>& spheres, const OrbitCamera& camera, int width, int height);

private:
    void drawSpheres(const std::vector<Sphere>& spheres, const OrbitCamera& camera, double aspect);
    unsigned surfelProgram_ = 0, sphereProgram_ = 0;
    unsigned quad_ = 0;  // the four corners, shared
    unsigned surfelVao_ = 0, surfelBuffer_ = 0;
    unsigned sphereVao_ = 0, sphereBuffer_ = 0;
};

}  // namespace bop::viz
