#pragma once
// OpenGL 3.3 core entry points, linked directly from libglvnd's libOpenGL (Linux): no loader.
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
