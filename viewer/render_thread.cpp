#include "viewer/render_thread.h"

#include "viewer/cell_view.h"

namespace epsray {

render_thread::render_thread(const world& w, const frame_params& fp, int width, int height, int threads,
                             size_t memory_budget, std::function<void()> on_finished)
    : w_(w),
      fp_(fp),
      width_(width),
      height_(height),
      on_finished_(std::move(on_finished)),
      pool_(threads),
      trees_(w.prim_bounds, memory_budget, size_t(width) * size_t(height)) {
  fp_.trees = fp_.mode == render_mode::base ? nullptr : &trees_;
  fp_.reproj = &reproj_;
  fp_.reasons = true;  // the reasons and paths displays
  pool_.warm_up();
  thread_ = std::thread([this] { loop(); });
}

render_thread::~render_thread() {
  {
    std::lock_guard lock(m_);
    stop_ = true;
  }
  wake_.notify_one();
  thread_.join();
}

std::uint64_t render_thread::request(const render_request& r) {
  std::uint64_t id;
  {
    std::lock_guard lock(m_);
    pending_ = r;
    id = ++pending_id_;
  }
  wake_.notify_one();
  return id;
}

bool render_thread::take(shown_frame& f, std::vector<camera_view>& rendered) {
  std::lock_guard lock(m_);
  if (!ready_new_) return false;
  std::swap(f, ready_);  // buffers move between the two frames: no copy, no allocation
  rendered.clear();
  std::swap(rendered, rendered_);
  ready_new_ = false;
  return true;
}

std::uint64_t render_thread::finished_id() {
  std::lock_guard lock(m_);
  return finished_id_;
}

std::string render_thread::error() {
  std::lock_guard lock(m_);
  return error_;
}

void render_thread::loop() {
  shown_frame work;  // filled outside the lock, then swapped with ready_
  std::uint64_t done = 0;
  for (;;) {
    render_request r;
    std::uint64_t id;
    {
      std::unique_lock lock(m_);
      wake_.wait(lock, [&] { return stop_ || pending_id_ > done; });
      if (stop_) return;
      r = pending_, id = pending_id_;
    }
    try {
      frame_params fp = fp_;
      fp.interp.eps = r.eps, fp.camera_moving = r.moving;
      const camera cam = make_camera(r.view, width_, height_);
      const frame_result fr = render_frame(pool_, w_, cam, fp);
      fill_shown_frame(fr, work);
      work.cells_object = -1;
      if (r.cells)
        work.cells_object = paint_cells(pool_, w_, cam, trees_, r.pick_x, r.pick_y, fr.img, cell_scratch_,
                                        work.rgb[size_t(display_mode::cells)]);
      else work.rgb[size_t(display_mode::cells)] = work.rgb[size_t(display_mode::image)];
    } catch (const std::exception& e) {
      {
        std::lock_guard lock(m_);
        error_ = e.what();
      }
      if (on_finished_) on_finished_();
      return;
    }
    work.id = id, work.view = r.view, work.eps = r.eps;
    done = id;
    {
      std::lock_guard lock(m_);
      std::swap(work, ready_);
      ready_new_ = true;
      finished_id_ = id;
      rendered_.push_back(r.view);
    }
    if (on_finished_) on_finished_();
  }
}

}  // namespace epsray
