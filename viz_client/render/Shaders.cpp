#include "render/Shaders.hpp"

#include "bop/common/Error.hpp"
#include "render/Gl.hpp"

#include <string>

namespace bop::viz::shaders {

// Attribute 0 is the quad corner in -1..1 (per vertex); the rest are per instance.
const char* const kSurfelVertex = R"(#version 330 core
layout(location = 0) in vec2 corner;
layout(location = 1) in vec3 centre;
layout(location = 2) in vec3 normal;
layout(location = 3) in float radius;
layout(location = 4) in vec4 colour;
uniform mat4 view;
uniform mat4 projection;
out vec2 vCorner;
out vec3 vNormalView;
out vec4 vColour;
void main() {
    vec3 n = normalize(normal);
    vec3 helper = abs(n.z) < 0.9 ? vec3(0.0, 0.0, 1.0) : vec3(1.0, 0.0, 0.0);
    vec3 t = normalize(cross(n, helper));
    vec3 b = cross(n, t);
    vec3 world = centre + radius * (corner.x * t + corner.y * b);
    gl_Position = projection * view * vec4(world, 1.0);
    vCorner = corner;
    vNormalView = mat3(view) * n;
    vColour = colour;
}
)";

const char* const kSurfelFragment = R"(#version 330 core
in vec2 vCorner;
in vec3 vNormalView;
in vec4 vColour;
out vec4 fragColour;
void main() {
    if (dot(vCorner, vCorner) > 1.0) discard;
    float light = abs(normalize(vNormalView).z);  // headlight; both faces lit
    fragColour = vec4(vColour.rgb * (0.35 + 0.65 * light), 1.0);
}
)";

// The quad lies in the plane through the sphere's centre facing the eye, 1.5 radii wide each
// way so that the perspective silhouette fits; fragments off the sphere are discarded.
const char* const kSphereVertex = R"(#version 330 core
layout(location = 0) in vec2 corner;
layout(location = 1) in vec3 centre;
layout(location = 2) in float radius;
layout(location = 3) in vec4 colour;
uniform mat4 view;
uniform mat4 projection;
out vec3 vPosView;
flat out vec3 vCentreView;
flat out float vRadius;
flat out vec4 vColour;
void main() {
    vec3 c = (view * vec4(centre, 1.0)).xyz;
    vec3 p = c + vec3(corner * radius * 1.5, 0.0);
    gl_Position = projection * vec4(p, 1.0);
    vPosView = p;
    vCentreView = c;
    vRadius = radius;
    vColour = colour;
}
)";

const char* const kSphereFragment = R"(#version 330 core
in vec3 vPosView;
flat in vec3 vCentreView;
flat in float vRadius;
flat in vec4 vColour;
uniform mat4 projection;
out vec4 fragColour;
void main() {
    vec3 d = normalize(vPosView);  // the ray from the eye, at the origin of view space
    float b = dot(d, vCentreView);
    float disc = b * b - (dot(vCentreView, vCentreView) - vRadius * vRadius);
    if (disc < 0.0) discard;
    vec3 hit = d * (b - sqrt(disc));
    vec3 n = (hit - vCentreView) / vRadius;
    vec4 clip = projection * vec4(hit, 1.0);
    gl_FragDepth = 0.5 * clip.z / clip.w + 0.5;
    float light = max(dot(n, -d), 0.0);
    fragColour = vec4(vColour.rgb * (0.35 + 0.65 * light), vColour.a);
}
)";

namespace {

unsigned compile(GLenum type, const char* source, const char* what) {
    const GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &source, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[2048] = {};
        glGetShaderInfoLog(s, sizeof log, nullptr, log);
        glDeleteShader(s);
        throw Error(what, std::string(type == GL_VERTEX_SHADER ? "vertex" : "fragment") + " shader: " + log);
    }
    return s;
}

}  // namespace

unsigned buildProgram(const char* vertex, const char* fragment, const char* what) {
    const GLuint vs = compile(GL_VERTEX_SHADER, vertex, what), fs = compile(GL_FRAGMENT_SHADER, fragment, what);
    const GLuint p = glCreateProgram();
    glAttachShader(p, vs);
    glAttachShader(p, fs);
    glLinkProgram(p);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[2048] = {};
        glGetProgramInfoLog(p, sizeof log, nullptr, log);
        glDeleteProgram(p);
        throw Error(what, std::string("linking: ") + log);
    }
    return p;
}

}  // namespace bop::viz::shaders
