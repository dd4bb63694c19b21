// The viewer's render thread: renders the newest requested camera in full mode on the
// worker pool, keeping the linetrees and last frame's cells between frames, and hands
// finished frames to the window thread without ever making it wait.
#pragma once
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "accel/world.h"
#include "sched/frame_render.h"
#include "viewer/frame_bytes.h"

namespace epsray {

struct render_request {
  camera_view view;
  float eps = 0;
  bool cells = false;           // paint the cells display (it costs a visibility ray a pixel)
  float pick_x = -1, pick_y = -1;  // its object: under this point, fractions of the image (negative: none)
  bool moving = false;          // the camera moves (frame_params::camera_moving)
};

class render_thread {
 public:
  // `fp` gives the mode and interpolation settings; eps comes with each request.
  // `on_finished` runs on the render thread after each frame (it wakes the window thread).
  // memory_budget: the linetrees' (bytes; 0: none), as --memory-mb.
  render_thread(const world& w, const frame_params& fp, int width, int height, int threads, size_t memory_budget,
                std::function<void()> on_finished);
  ~render_thread();  // finishes the frame in hand, then joins
  render_thread(const render_thread&) = delete;
  render_thread& operator=(const render_thread&) = delete;

  // Replaces any request not started yet (the newest camera wins); returns its id (1, 2, ...).
  std::uint64_t request(const render_request& r);
  // Swaps the newest finished frame into `f`, and into `rendered` the camera of every frame
  // finished since the last take (some may have been replaced before they were shown).
  // False, touching nothing, when no frame finished since the last take.
  bool take(shown_frame& f, std::vector<camera_view>& rendered);
  std::uint64_t finished_id();
  std::string error();  // why the render thread stopped, or empty
  int threads() const { return pool_.threads(); }

 private:
  void loop();

  const world& w_;
  frame_params fp_;
  int width_, height_;
  std::function<void()> on_finished_;
  workers pool_;
  linetree_set trees_;
  reprojection_state reproj_;
  std::vector<const lt_node*> cell_scratch_;

  std::mutex m_;
  std::condition_variable wake_;
  render_request pending_;
  std::uint64_t pending_id_ = 0, finished_id_ = 0;
  bool stop_ = false;
  shown_frame ready_;  // finished, not yet taken
  bool ready_new_ = false;
  std::vector<camera_view> rendered_;
  std::string error_;
  std::thread thread_;  // last: starts once everything above exists
};

}  // namespace epsray
