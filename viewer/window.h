// The viewer's window: GLFW, its OpenGL context and Dear ImGui, opened together and closed
// in reverse order, and the input the window receives (none while the HUD has it).
#pragma once
#include <string>
#include <vector>

struct GLFWwindow;

namespace epsray {

class window {
 public:
  // Throws usage_error (one line, exit 2) when there is no display to open a window on,
  // std::runtime_error when the display has no usable OpenGL.
  window(int width, int height, const std::string& title, bool vsync);
  ~window();
  window(const window&) = delete;
  window& operator=(const window&) = delete;

  bool closing() const;
  // Waits for input or wake() at most `seconds` (0: only what is there).
  void wait_events(double seconds);
  // Keys pressed (GLFW codes) and scroll steps since the last call.
  void take_input(std::vector<int>& presses, double& scroll);
  bool key_held(int key) const;
  // Cursor movement in pixels since the last call while the left button drags (a drag that
  // starts on the HUD belongs to the HUD).
  void drag(float& dx, float& dy);
  // A right click since the last call (not on the HUD): where, as fractions of the window.
  bool take_pick(float& fx, float& fy);
  void framebuffer_size(int& width, int& height) const;
  // The HUD has the mouse or the keyboard (hover, typing): it wants prompt redraws.
  bool hud_busy() const;
  // Starts a Dear ImGui frame (after events are polled).
  void begin_frame();
  // Clears the back buffer and draws this frame's Dear ImGui lists (the rendered image is
  // on the background list); `present` swaps it to the screen.
  void end_frame();
  void present();
  // Wakes a thread waiting for events; safe from any thread while the window is open.
  static void wake();

 private:
  static void on_key(GLFWwindow* w, int key, int scancode, int action, int mods);
  static void on_scroll(GLFWwindow* w, double dx, double dy);

  GLFWwindow* w_ = nullptr;
  std::vector<int> presses_;
  double scroll_ = 0;
  bool dragging_ = false;
  bool right_down_ = false;
  double cursor_x_ = 0, cursor_y_ = 0;
};

}  // namespace epsray
