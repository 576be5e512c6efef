// bop-viewer's window: GLFW with an OpenGL 3.3 core context, Dear ImGui's GLFW and OpenGL3
// backends, pointer and keys handed to ViewerCore unless the panel wants them.
#include "app/ViewerCore.hpp"
#include "app/ViewerLoops.hpp"
#include "bop/common/Canvas.hpp"
#include "bop/common/Error.hpp"
#include "render/Gl.hpp"
#include "render/Offscreen.hpp"

#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <chrono>
#include <cstdio>
#include <filesystem>

namespace bop::viz {
namespace {

ViewerCore& coreOf(GLFWwindow* w) {
    return *static_cast<ViewerCore*>(glfwGetWindowUserPointer(w));
}

// The pointer in NDC of the window (x right, y up, -1..1) and the window's aspect.
void pointer(GLFWwindow* w, double& x, double& y, double& aspect) {
    int width = 1, height = 1;
    glfwGetWindowSize(w, &width, &height);
    double px = 0, py = 0;
    glfwGetCursorPos(w, &px, &py);
    x = 2 * px / std::max(width, 1) - 1;
    y = 1 - 2 * py / std::max(height, 1);
    aspect = double(std::max(width, 1)) / std::max(height, 1);
}

void onButton(GLFWwindow* w, int button, int action, int) {
    if (ImGui::GetIO().WantCaptureMouse && action == GLFW_PRESS) return;
    const int b = button == GLFW_MOUSE_BUTTON_LEFT ? 0 : button == GLFW_MOUSE_BUTTON_RIGHT ? 1 : -1;
    if (b < 0) return;
    double x, y, aspect;
    pointer(w, x, y, aspect);
    if (action == GLFW_PRESS)
        coreOf(w).press(b, x, y, aspect);
    else
        coreOf(w).release(b);
}

void onMove(GLFWwindow* w, double, double) {
    double x, y, aspect;
    pointer(w, x, y, aspect);
    coreOf(w).move(x, y, aspect);
}

void onScroll(GLFWwindow* w, double, double dy) {
    if (!ImGui::GetIO().WantCaptureMouse) coreOf(w).scroll(dy);
}

void onKey(GLFWwindow* w, int key, int, int action, int) {
    if (action != GLFW_PRESS || ImGui::GetIO().WantCaptureKeyboard) return;
    if (key == GLFW_KEY_ESCAPE) glfwSetWindowShouldClose(w, GLFW_TRUE);
    if (key == GLFW_KEY_F || key == GLFW_KEY_R || key == GLFW_KEY_P || key == GLFW_KEY_N || key == GLFW_KEY_S)
        coreOf(w).key(char(key));  // GLFW's letter keys are their upper-case ASCII codes
}

}  // namespace

int runWindow(ViewerLink& link, const LoopOptions& o) {
    glfwSetErrorCallback([](int, const char* what) { std::fprintf(stderr, "bop-viewer: GLFW: %s\n", what); });
    if (!glfwInit()) throw Error("bop-viewer", "no display for a window (GLFW could not start); run with --headless");
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    GLFWwindow* window = glfwCreateWindow(o.width, o.height, "BoP viewer", nullptr, nullptr);
    if (!window) {
        glfwTerminate();
        throw Error("bop-viewer", "no OpenGL 3.3 core window could be made; run with --headless");
    }
    glfwMakeContextCurrent(window);
    glfwSwapInterval(1);
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left in the working folder
    {
        ViewerCore core(link);
        core.panel.hideAtStart = o.hide;
        glfwSetWindowUserPointer(window, &core);
        glfwSetMouseButtonCallback(window, onButton);
        glfwSetCursorPosCallback(window, onMove);
        glfwSetScrollCallback(window, onScroll);
        glfwSetKeyCallback(window, onKey);
        ImGui_ImplGlfw_InitForOpenGL(window, true);  // chains to the callbacks above
        ImGui_ImplOpenGL3_Init("#version 330 core");
        std::printf("bop-viewer: window on %s\n", reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
        std::fflush(stdout);
        int drawnNew = 0, shots = 0;
        const auto t0 = std::chrono::steady_clock::now();
        while (!glfwWindowShouldClose(window)) {
            glfwPollEvents();
            const double now = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            if (link.status().state == LinkState::GaveUp) throw Error("bop-viewer", link.status().message);
            const bool fresh = core.poll(now);
            int width = 0, height = 0;
            glfwGetFramebufferSize(window, &width, &height);
            if (width == 0 || height == 0) {  // minimised: wait for events instead of spinning
                glfwWaitEventsTimeout(0.1);
                continue;
            }
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
            core.draw(width, height, now, o.panel, [] { ImGui_ImplGlfw_NewFrame(); });
            drawnNew += fresh;
            // The picture drawn after a close request (or the --frames-th new frame) is the last.
            const bool last = (o.frames > 0 && drawnNew >= o.frames) || glfwWindowShouldClose(window);
            if (core.takeScreenshotRequest() || (last && !o.screenshot.empty())) {
                char name[40];
                std::snprintf(name, sizeof name, "screenshot-%03d.png", ++shots);
                const std::string path =
                    last && !o.screenshot.empty() ? o.screenshot : (std::filesystem::path(o.outDir) / name).string();
                if (!std::filesystem::path(path).parent_path().empty())
                    std::filesystem::create_directories(std::filesystem::path(path).parent_path());
                glReadBuffer(GL_BACK);
                Canvas::fromRgb(width, height, readBoundRgb(width, height)).writePng(path);
                std::printf("bop-viewer: screenshot %s\n", path.c_str());
                std::fflush(stdout);
            }
            glfwSwapBuffers(window);
            if (last) break;
        }
        std::printf("bop-viewer: drew %d new frames\n", drawnNew);
        ImGui_ImplOpenGL3_Shutdown();
        ImGui_ImplGlfw_Shutdown();
    }
    ImGui::DestroyContext();
    glfwDestroyWindow(window);
    glfwTerminate();
    return 0;
}

}  // namespace bop::viz
