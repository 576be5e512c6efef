#include "render/InstanceRenderer.hpp"

#include "render/Gl.hpp"
#include "render/Shaders.hpp"

#include <cstddef>

namespace bop::viz {
namespace {

constexpr float kCorners[8] = {-1, -1, 1, -1, -1, 1, 1, 1};  // a triangle strip

// Per-instance attribute `index` of `size` components at `offset` in records of `stride` bytes.
void instanceAttribute(GLuint index, GLint size, GLenum type, bool normalised, std::size_t stride, std::size_t offset) {
    glEnableVertexAttribArray(index);
    glVertexAttribPointer(index, size, type, normalised ? GL_TRUE : GL_FALSE, GLsizei(stride),
                          reinterpret_cast<const void*>(offset));
    glVertexAttribDivisor(index, 1);
}

void cornerAttribute(GLuint quad) {
    glBindBuffer(GL_ARRAY_BUFFER, quad);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
}

void setCamera(GLuint program, const OrbitCamera& camera, double aspect) {
    const Eigen::Matrix4f view = camera.view().cast<float>(), projection = camera.projection(aspect).cast<float>();
    glUseProgram(program);
    glUniformMatrix4fv(glGetUniformLocation(program, "view"), 1, GL_FALSE, view.data());
    glUniformMatrix4fv(glGetUniformLocation(program, "projection"), 1, GL_FALSE, projection.data());
}

}  // namespace

InstanceRenderer::InstanceRenderer() {
    surfelProgram_ = shaders::buildProgram(shaders::kSurfelVertex, shaders::kSurfelFragment, "surfel shader");
    sphereProgram_ = shaders::buildProgram(shaders::kSphereVertex, shaders::kSphereFragment, "sphere shader");
    glGenBuffers(1, &quad_);
    glBindBuffer(GL_ARRAY_BUFFER, quad_);
    glBufferData(GL_ARRAY_BUFFER, sizeof kCorners, kCorners, GL_STATIC_DRAW);

    glGenVertexArrays(1, &surfelVao_);
    glBindVertexArray(surfelVao_);
    cornerAttribute(quad_);
    glGenBuffers(1, &surfelBuffer_);
    glBindBuffer(GL_ARRAY_BUFFER, surfelBuffer_);
    instanceAttribute(1, 3, GL_FLOAT, false, sizeof(Surfel), offsetof(Surfel, position));
    instanceAttribute(2, 3, GL_FLOAT, false, sizeof(Surfel), offsetof(Surfel, normal));
    instanceAttribute(3, 1, GL_FLOAT, false, sizeof(Surfel), offsetof(Surfel, radius));
    instanceAttribute(4, 4, GL_UNSIGNED_BYTE, true, sizeof(Surfel), offsetof(Surfel, rgba));

    glGenVertexArrays(1, &sphereVao_);
    glBindVertexArray(sphereVao_);
    cornerAttribute(quad_);
    glGenBuffers(1, &sphereBuffer_);
    glBindBuffer(GL_ARRAY_BUFFER, sphereBuffer_);
    instanceAttribute(1, 3, GL_FLOAT, false, sizeof(Sphere), offsetof(Sphere, position));
    instanceAttribute(2, 1, GL_FLOAT, false, sizeof(Sphere), offsetof(Sphere, radius));
    instanceAttribute(3, 4, GL_UNSIGNED_BYTE, true, sizeof(Sphere), offsetof(Sphere, rgba));
    glBindVertexArray(0);
}

InstanceRenderer::~InstanceRenderer() {
    const GLuint buffers[] = {quad_, surfelBuffer_, sphereBuffer_}, arrays[] = {surfelVao_, sphereVao_};
    glDeleteBuffers(3, buffers);
    glDeleteVertexArrays(2, arrays);
    glDeleteProgram(surfelProgram_);
    glDeleteProgram(sphereProgram_);
}

void InstanceRenderer::draw(const Instances& in, const OrbitCamera& camera, int width, int height,
                            const std::array<float, 3>& background) {
    const double aspect = double(width) / double(height);
    glViewport(0, 0, width, height);
    glClearColor(background[0], background[1], background[2], 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);  // discs are seen from both sides
    if (!in.surfels.empty()) {
        setCamera(surfelProgram_, camera, aspect);
        glBindVertexArray(surfelVao_);
        glBindBuffer(GL_ARRAY_BUFFER, surfelBuffer_);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(in.surfels.size() * sizeof(Surfel)), in.surfels.data(),
                     GL_STREAM_DRAW);
        glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, GLsizei(in.surfels.size()));
    }
    drawSpheres(in.spheres, camera, aspect);
}

void InstanceRenderer::drawSpheres(const std::vector<Sphere>& spheres, const OrbitCamera& camera, double aspect) {
    if (spheres.empty()) return;
    setCamera(sphereProgram_, camera, aspect);
    glBindVertexArray(sphereVao_);
    glBindBuffer(GL_ARRAY_BUFFER, sphereBuffer_);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(spheres.size() * sizeof(Sphere)), spheres.data(), GL_STREAM_DRAW);
    glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, GLsizei(spheres.size()));
    glBindVertexArray(0);
}

void InstanceRenderer::drawTranslucent(const std::vector<Sphere>& spheres, const OrbitCamera& camera, int width,
                                       int height) {
    glViewport(0, 0, width, height);
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glDepthMask(GL_FALSE);  // what lies behind still shows through
    drawSpheres(spheres, camera, double(width) / double(height));
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
}

}  // namespace bop::viz
