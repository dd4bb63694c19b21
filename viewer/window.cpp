#include "viewer/window.h"

#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <cstdlib>
#include <stdexcept>

#include "args.h"

namespace epsray {

namespace {

std::string glfw_error;  // GLFW reports failures through a callback, not return values

void on_glfw_error(int, const char* what) { glfw_error = what; }

}  // namespace

window::window(int width, int height, const std::string& title, bool vsync) {
  glfwSetErrorCallback(on_glfw_error);
  const char* display = std::getenv("DISPLAY");
  if (!display || !*display)
    throw usage_error("epsray: view needs a display: DISPLAY is not set (run it under X11, or xvfb-run)");
  if (!glfwInit()) throw usage_error("epsray: view needs a display: " + glfw_error);
  w_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!w_) {
    glfwTerminate();
    throw std::runtime_error("cannot open an OpenGL window: " + glfw_error);
  }
  glfwSetWindowUserPointer(w_, this);
  glfwSetKeyCallback(w_, on_key);
  glfwSetScrollCallback(w_, on_scroll);
  glfwMakeContextCurrent(w_);
  glfwSwapInterval(vsync ? 1 : 0);
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left in the working folder
  ImGui::StyleColorsDark();
  // The back end calls the key and scroll callbacks set above before its own.
  ImGui_ImplGlfw_InitForOpenGL(w_, true);
  if (!ImGui_ImplOpenGL3_Init("#version 130")) {
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    glfwDestroyWindow(w_);
    glfwTerminate();
    throw std::runtime_error("the display's OpenGL cannot run Dear ImGui (it needs OpenGL 3.0)");
  }
}

window::~window() {
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(w_);
  glfwTerminate();
}

bool window::closing() const { return glfwWindowShouldClose(w_); }

void window::on_key(GLFWwindow* w, int key, int, int action, int) {
  if (action == GLFW_PRESS && !ImGui::GetIO().WantCaptureKeyboard)
    static_cast<window*>(glfwGetWindowUserPointer(w))->presses_.push_back(key);
}

void window::on_scroll(GLFWwindow* w, double, double dy) {
  if (!ImGui::GetIO().WantCaptureMouse) static_cast<window*>(glfwGetWindowUserPointer(w))->scroll_ += dy;
}

void window::wait_events(double seconds) {
  if (seconds > 0) glfwWaitEventsTimeout(seconds);
  else glfwPollEvents();
}

void window::take_input(std::vector<int>& presses, double& scroll) {
  presses.clear();
  std::swap(presses, presses_);
  scroll = scroll_, scroll_ = 0;
}

bool window::key_held(int key) const {
  return !ImGui::GetIO().WantCaptureKeyboard && glfwGetKey(w_, key) == GLFW_PRESS;
}

void window::drag(float& dx, float& dy) {
  dx = dy = 0;
  double x, y;
  glfwGetCursorPos(w_, &x, &y);
  const bool down = glfwGetMouseButton(w_, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
  if (down && dragging_) dx = float(x - cursor_x_), dy = float(y - cursor_y_);
  dragging_ = down && (dragging_ || !ImGui::GetIO().WantCaptureMouse);
  cursor_x_ = x, cursor_y_ = y;
}

bool window::take_pick(float& fx, float& fy) {
  const bool down = glfwGetMouseButton(w_, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
  const bool clicked = down && !right_down_ && !ImGui::GetIO().WantCaptureMouse;
  right_down_ = down;
  if (!clicked) return false;
  double x, y;
  int ww = 0, wh = 0;
  glfwGetCursorPos(w_, &x, &y);
  glfwGetWindowSize(w_, &ww, &wh);
  if (ww <= 0 || wh <= 0) return false;
  fx = float(x / ww), fy = float(y / wh);
  return true;
}

void window::framebuffer_size(int& width, int& height) const { glfwGetFramebufferSize(w_, &width, &height); }

bool window::hud_busy() const { return ImGui::GetIO().WantCaptureMouse || ImGui::GetIO().WantCaptureKeyboard; }

void window::begin_frame() {
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
}

void window::end_frame() {
  ImGui::Render();
  int w = 0, h = 0;
  framebuffer_size(w, h);
  glViewport(0, 0, w, h);
  glClearColor(0, 0, 0, 1);
  glClear(GL_COLOR_BUFFER_BIT);
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

void window::present() { glfwSwapBuffers(w_); }

void window::wake() { glfwPostEmptyEvent(); }

}  // namespace epsray
