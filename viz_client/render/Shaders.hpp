#pragma once
// GLSL 3.30 sources of the instance renderer (InstanceRenderer.hpp) and the helper that builds a
// program from them.
namespace bop::viz::shaders {

extern const char* const kSurfelVertex;
extern const char* const kSurfelFragment;
extern const char* const kSphereVertex;
extern const char* const kSphereFragment;

// Compiles and links; bop::Error naming `what` with the driver's log on failure.
unsigned buildProgram(const char* vertex, const char* fragment, const char* what);

}  // namespace bop::viz::shaders
