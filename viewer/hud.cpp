#include "viewer/hud.h"

#include <imgui.h>

#include <algorithm>

namespace epsray {

namespace {

ImVec4 colour(const rgb8& c) { return ImVec4(c[0] / 255.0f, c[1] / 255.0f, c[2] / 255.0f, 1); }

void path_row(const char* name, const rgb8& c, std::uint64_t pixels, double all, double ms) {
  ImGui::TextColored(colour(c), "%-6s", name);
  ImGui::SameLine();
  ImGui::Text("%5.1f%% of pixels  %7.1f ms", all > 0 ? 100.0 * double(pixels) / all : 0.0, ms);
}

}  // namespace

void draw_hud(viewer_state& s, const shown_frame& f, const frame_times& times, const char* scene, int threads) {
  if (!s.hud) return;
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowBgAlpha(0.75f);
  if (!ImGui::Begin("epsray view", nullptr, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoFocusOnAppearing)) {
    ImGui::End();
    return;
  }
  const frame_stats& st = f.stats;
  ImGui::Text("%s  %dx%d  %d threads", scene, f.width, f.height, threads);
  ImGui::Text("frame %.1f ms (%.1f frames/s; reproject %.1f ms)  window %.0f fps", st.ms,
              st.ms > 0 ? 1000 / st.ms : 0.0, st.reproject_ms, double(ImGui::GetIO().Framerate));
  ImGui::PlotLines("##ms", times.ms.data(), times.count, times.count < int(times.ms.size()) ? 0 : times.next,
                   "frame ms", 0.0f, FLT_MAX, ImVec2(300, 50));
  // Thread time per path, summed over the workers (the paper's Table 1 costs).
  const double all = double(st.pixels.fast + st.pixels.interp + st.pixels.base);
  path_row("fast", path_colours[0], st.pixels.fast, all, st.path_ms.fast);
  if (st.pixels.span)  // the part of fast filled in screen space along spans
    ImGui::Text("  span  %5.1f%% of pixels  %7.1f ms", 100.0 * double(st.pixels.span) / all, st.path_ms.span);
  path_row("interp", path_colours[1], st.pixels.interp, all, st.path_ms.interp);
  path_row("base", path_colours[2], st.pixels.base, all, st.path_ms.base);
  ImGui::Text("linetrees and images %.1f MB", double(st.memory_bytes) / 1e6);

  float typed = s.eps;
  ImGui::SetNextItemWidth(100);
  if (ImGui::InputFloat("epsilon", &typed, 0, 0, "%.4g", ImGuiInputTextFlags_EnterReturnsTrue))
    s.eps = std::clamp(typed, 0.0f, max_eps);
  ImGui::SameLine();
  ImGui::Text("moving %.4g, this frame %.4g", double(moving_eps(s.eps)), double(f.eps));
  ImGui::Text("display: %s (Tab)%s%s", display_mode_name(s.mode), s.rec.on ? "  REC" : "",
              s.play >= 0 ? "  PLAY" : "");
  if (!s.note.empty()) ImGui::TextUnformatted(s.note.c_str());
  ImGui::TextUnformatted("W A S D Q E move, left drag looks, + - or scroll: speed\n"
                         "[ ] epsilon, Tab display, right click: cells of an object, R reset, P record, L play, F1 HUD");
  if (ImGui::CollapsingHeader("keys")) {
    ImGui::TextUnformatted("left drag: look");
    for (const key_binding& b : key_bindings()) ImGui::Text("%-4s %s", b.name, b.help);
  }
  ImGui::End();
}

}  // namespace epsray
