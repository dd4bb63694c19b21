#include "viewer/hud.h"

#include <imgui.h>

#include <algorithm>
#include <cfloat>
#include <filesystem>
#include <string>
#include <utility>

#include "interp/interp_shade.h"

namespace epsray {

namespace {

// How long the compact HUD shows what the last key did.
constexpr double note_seconds = 4;

// Overlays that only show things: clicks and drags go through them to the picture.
constexpr ImGuiWindowFlags overlay_flags = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                                           ImGuiWindowFlags_NoInputs | ImGuiWindowFlags_NoFocusOnAppearing |
                                           ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoSavedSettings;

ImVec4 colour(const rgb8& c) { return ImVec4(c[0] / 255.0f, c[1] / 255.0f, c[2] / 255.0f, 1); }

double share(std::uint64_t pixels, const pixel_counts& p) {
  const double all = double(p.fast + p.interp + p.base);
  return all > 0 ? 100.0 * double(pixels) / all : 0.0;
}

double frames_per_second(const frame_stats& st) { return st.ms > 0 ? 1000 / st.ms : 0.0; }

// A colour swatch and its name, on the current line.
void swatch(const rgb8& c, const char* name) {
  ImGui::ColorButton(name, colour(c), ImGuiColorEditFlags_NoTooltip | ImGuiColorEditFlags_NoDragDrop,
                     ImVec2(ImGui::GetTextLineHeight(), ImGui::GetTextLineHeight()));
  ImGui::SameLine(0, 4);
  ImGui::TextUnformatted(name);
}

// The two lines over the top left: rates, the bound and where the pixels came from; a third
// while a note is fresh (it may name a file: too long for the second).
void draw_compact(const viewer_state& s, const shown_frame& f, bool fresh_note) {
  ImGui::SetNextWindowPos(ImVec2(4, 4));
  ImGui::SetNextWindowBgAlpha(0.6f);
  ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(6, 3));
  ImGui::PushStyleVar(ImGuiStyleVar_ItemSpacing, ImVec2(6, 2));
  if (ImGui::Begin("##compact", nullptr, overlay_flags)) {
    const frame_stats& st = f.stats;
    ImGui::Text("%.1f fps  frame %.1f ms  eps %.4g", frames_per_second(st), st.ms, double(s.eps));
    if (f.id && f.eps != s.eps) {  // a moving frame, or one from before the bound changed
      ImGui::SameLine();
      ImGui::TextDisabled("(this frame %.4g)", double(f.eps));
    }
    const std::uint64_t counts[3] = {st.pixels.fast, st.pixels.interp, st.pixels.base};
    const char* names[3] = {"fast", "interp", "traced"};
    for (int i = 0; i < 3; ++i) {
      if (i) ImGui::SameLine();
      ImGui::TextColored(colour(path_colours[size_t(i)]), "%s", names[i]);
      ImGui::SameLine(0, 4);
      ImGui::Text("%.0f%%", share(counts[i], st.pixels));
    }
    for (const auto& [on, flag] : {std::pair{s.rec.on, "REC"}, std::pair{s.play >= 0, "PLAY"}}) {
      if (!on) continue;
      ImGui::SameLine();
      ImGui::TextColored(colour(path_colours[2]), "%s", flag);
    }
    ImGui::SameLine();
    ImGui::TextDisabled("F1 panel, H hide");
    if (fresh_note && !s.note.empty()) ImGui::TextUnformatted(s.note.c_str());
  }
  ImGui::End();
  ImGui::PopStyleVar(2);
}

void path_row(const char* name, const rgb8& c, std::uint64_t pixels, const pixel_counts& all, double ms) {
  ImGui::TextColored(colour(c), "%-6s", name);
  ImGui::SameLine();
  ImGui::Text("%5.1f%% of pixels  %7.1f thread ms", share(pixels, all), ms);
}

// A key (or mouse action) and what it does, on the current line.
void key_help(const char* key, const char* help) {
  ImGui::TextColored(ImVec4(1, 0.85f, 0.4f, 1), "%s", key);
  ImGui::SameLine(0, 6);
  ImGui::TextUnformatted(help);
}

// The keys three to a row, short enough for 640 pixels; movement and the mouse below.
void key_help_table() {
  ImGui::PushStyleVar(ImGuiStyleVar_CellPadding, ImVec2(8, 1));
  if (ImGui::BeginTable("keys", 3, ImGuiTableFlags_SizingFixedFit)) {
    for (const key_binding& b : key_bindings()) {
      if (b.held) continue;
      ImGui::TableNextColumn();
      key_help(b.name, b.help);
    }
    ImGui::EndTable();
  }
  ImGui::PopStyleVar();
  std::string moves, helps;
  for (const key_binding& b : key_bindings()) {
    if (!b.held) continue;
    if (!moves.empty()) moves += ' ', helps += ' ';
    moves += b.name, helps += b.help;
  }
  key_help(moves.c_str(), helps.c_str());
  key_help("left drag", "look");
  ImGui::SameLine();
  key_help("wheel", "speed");
  ImGui::SameLine();
  key_help("right-click", "an object's cells");
}

void draw_full(viewer_state& s, const shown_frame& f, const frame_times& times, const char* scene, int threads) {
  ImGui::SetNextWindowPos(ImVec2(4, 4), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowBgAlpha(0.75f);
  if (!ImGui::Begin("epsray view (F1: compact, H: hide)", nullptr,
                    ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoFocusOnAppearing)) {
    ImGui::End();
    return;
  }
  const frame_stats& st = f.stats;
  // The file name alone: a long folder would widen the panel past the window.
  ImGui::Text("%s  %dx%d  %d threads", std::filesystem::path(scene).filename().c_str(), f.width, f.height, threads);
  ImGui::Text("frame %.1f ms (%.1f fps; reproject %.1f ms)  window %.0f fps", st.ms, frames_per_second(st),
              st.reproject_ms, double(ImGui::GetIO().Framerate));
  ImGui::PlotLines("##ms", times.ms.data(), times.count, times.count < int(times.ms.size()) ? 0 : times.next,
                   "frame ms", 0.0f, FLT_MAX, ImVec2(300, 40));
  // Thread time per path, summed over the workers (the paper's Table 1 costs): with several
  // threads it adds up to more than the frame's time.
  path_row("fast", path_colours[0], st.pixels.fast, st.pixels, st.path_ms.fast);
  if (st.pixels.span)  // the part of fast filled in screen space along spans
    ImGui::Text("  span %5.1f%% of pixels  %7.1f thread ms", share(st.pixels.span, st.pixels), st.path_ms.span);
  path_row("interp", path_colours[1], st.pixels.interp, st.pixels, st.path_ms.interp);
  path_row("traced", path_colours[2], st.pixels.base, st.pixels, st.path_ms.base);
  ImGui::Text("linetrees and images %.1f MB", double(st.memory_bytes) / 1e6);

  float typed = s.eps;
  ImGui::SetNextItemWidth(100);
  if (ImGui::InputFloat("epsilon", &typed, 0, 0, "%.4g", ImGuiInputTextFlags_EnterReturnsTrue))
    s.eps = std::clamp(typed, 0.0f, max_eps);
  ImGui::SameLine();
  ImGui::Text("moving %.4g, this frame %.4g", double(moving_eps(s.eps)), double(f.eps));
  ImGui::Text("display: %s (Tab: image, reasons, paths, cells)%s%s", display_mode_name(s.mode),
              s.rec.on ? "  REC" : "", s.play >= 0 ? "  PLAY" : "");
  if (!s.note.empty()) ImGui::TextUnformatted(s.note.c_str());
  ImGui::Separator();
  key_help_table();
  ImGui::End();
}

// Along the bottom of the window: what the diagnostic display's colours mean.
void draw_legend(const viewer_state& s, const shown_frame& f) {
  const ImVec2 win = ImGui::GetIO().DisplaySize;
  if (s.mode == display_mode::cells && f.cells_object < 0) {
    // Everything is dimmed: say how to pick, where a person looks.
    ImGui::SetNextWindowPos(ImVec2(win.x / 2, win.y / 2), ImGuiCond_Always, ImVec2(0.5f, 0.5f));
    ImGui::SetNextWindowBgAlpha(0.75f);
    if (ImGui::Begin("##hint", nullptr, overlay_flags))
      ImGui::TextUnformatted("right-click an object to see its linetree cells");
    ImGui::End();
    return;
  }
  ImGui::SetNextWindowPos(ImVec2(4, win.y - 4), ImGuiCond_Always, ImVec2(0, 1));
  ImGui::SetNextWindowBgAlpha(0.75f);
  if (ImGui::Begin("##legend", nullptr, overlay_flags)) {
    const auto reason = [](pixel_reason r) { swatch(reason_bytes()[size_t(r)], reason_names[size_t(r)]); };
    switch (s.mode) {
      case display_mode::reasons:
        reason(pixel_reason::interpolated);
        ImGui::SameLine();
        reason(pixel_reason::reprojected);
        ImGui::SameLine();
        reason(pixel_reason::traced);
        ImGui::TextUnformatted("traced, its cell failed:");
        for (pixel_reason r : {pixel_reason::discontinuity, pixel_reason::missed, pixel_reason::blocked,
                               pixel_reason::nonlinear}) {
          ImGui::SameLine();
          reason(r);
        }
        break;
      case display_mode::paths:
        swatch(path_colours[0], "fast (reprojected)");
        ImGui::SameLine();
        swatch(path_colours[1], "interp");
        ImGui::SameLine();
        swatch(path_colours[2], "traced");
        break;
      case display_mode::cells:
        ImGui::TextUnformatted("linetree cells of the picked object, outlined; right-click another");
        break;
      case display_mode::image: break;
    }
  }
  ImGui::End();
}

}  // namespace

void draw_hud(viewer_state& s, const shown_frame& f, const frame_times& times, const char* scene, int threads) {
  // When the last note came: the one window a viewer has, so the HUD's own memory.
  static int seen = 0;
  static double since = -note_seconds;
  if (s.note_serial != seen) seen = s.note_serial, since = ImGui::GetTime();
  if (!s.hud) return;
  if (s.hud_full) draw_full(s, f, times, scene, threads);
  else draw_compact(s, f, ImGui::GetTime() - since < note_seconds);
  if (s.mode != display_mode::image) draw_legend(s, f);
}

}  // namespace epsray
