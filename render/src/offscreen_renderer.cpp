#include "exoid/render/offscreen_renderer.hpp"

#include "exoid/core/format.hpp"
#include "exoid/sim/mujoco_hooks.hpp"

#include <GL/osmesa.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace exoid::render {

namespace {

constexpr long kMaxPixels = 8192L * 8192L;

void copyText(char* dst, std::size_t cap, const std::string& s) {
  const std::size_t n = std::min(cap - 1, s.size());
  std::memcpy(dst, s.data(), n);
  dst[n] = '\0';
}

// Rows of text in the overlay (its longer column) at mjr_overlay's line pitch, 5/4 of the font's
// character height (measured: 23 px a line for charHeight 18 at 640x480), and one more row of
// margin.
int textBandHeight_px(const Overlay& o, int char_height_px) {
  const auto lines = [](const std::string& t) { return t.empty() ? 0 : 1 + static_cast<int>(std::count(t.begin(), t.end(), '\n')); };
  return (std::max(lines(o.text_left), lines(o.text_right)) + 1) * char_height_px * 5 / 4;
}

int fontScaleFor(int height) {
  if (height <= 560) return mjFONTSCALE_100;
  if (height <= 900) return mjFONTSCALE_150;
  return mjFONTSCALE_200;
}

}  // namespace

void RenderOptions::validate() const {
  if (width < 16 || height < 16 || static_cast<long>(width) * height > kMaxPixels) {
    throw std::invalid_argument("image size must be at least 16x16 and at most 8192*8192 pixels, got " +
                                core::toText(width) + "x" + core::toText(height));
  }
  if (shadow_map_size < 256 || shadow_map_size > 8192) {
    throw std::invalid_argument("'shadow_map_size' must be in [256, 8192], got " + core::toText(shadow_map_size));
  }
  if (multisamples < 0 || multisamples > 8) {
    throw std::invalid_argument("'multisamples' must be in [0, 8], got " + core::toText(multisamples));
  }
  if (!std::isfinite(camera.distance_m) || camera.distance_m <= 0.0) {
    throw std::invalid_argument("'camera.distance_m' must be positive, got " + core::toText(camera.distance_m));
  }
  for (double v : camera.lookat) {
    if (!std::isfinite(v)) throw std::invalid_argument("'camera.lookat' must be finite");
  }
  if (!std::isfinite(camera.azimuth_deg) || !std::isfinite(camera.elevation_deg) || std::abs(camera.elevation_deg) >= 90.0) {
    throw std::invalid_argument("camera angles must be finite with |elevation| < 90 deg, got elevation " +
                                core::toText(camera.elevation_deg));
  }
}

struct OffscreenRenderer::Impl {
  OSMesaContext gl = nullptr;
  std::vector<unsigned char> gl_buffer;  // the context's default framebuffer (MuJoCo draws offscreen)
  mjvScene scene{};
  mjvCamera camera{};
  mjvOption option{};
  mjrContext context{};
  bool scene_made = false, context_made = false;
  std::vector<unsigned char> pixels;  // bottom-up, as read back
  Image image;
  std::vector<std::unique_ptr<mjvFigure>> figures;
  int width = 0, height = 0;

  void makeCurrent() {
    if (!OSMesaMakeCurrent(gl, gl_buffer.data(), GL_UNSIGNED_BYTE, width, height)) {
      GLint max_w = 0, max_h = 0;
      OSMesaGetIntegerv(OSMESA_MAX_WIDTH, &max_w);
      OSMesaGetIntegerv(OSMESA_MAX_HEIGHT, &max_h);
      throw std::runtime_error("cannot make the OSMesa context current on a " + core::toText(width) + "x" +
                               core::toText(height) + " buffer" +
                               (max_w > 0 ? " (OSMesa maximum " + core::toText(max_w) + "x" + core::toText(max_h) + ")"
                                          : std::string()));
    }
  }

  ~Impl() {
    if (gl && context_made && OSMesaMakeCurrent(gl, gl_buffer.data(), GL_UNSIGNED_BYTE, width, height)) {
      mjr_freeContext(&context);
    }
    if (scene_made) mjv_freeScene(&scene);
    if (gl) OSMesaDestroyContext(gl);
  }
};

OffscreenRenderer::OffscreenRenderer(mjModel* m, const RenderOptions& options)
    : options_(options), impl_(std::make_unique<Impl>()) {
  options_.validate();
  if (!m) throw std::invalid_argument("OffscreenRenderer: model is null");
  sim::installMujocoHooks();
  Impl& s = *impl_;
  s.width = options_.width;
  s.height = options_.height;
  // The offscreen framebuffer's size comes from the model (docs/mujoco.md note 11): set before mjr_makeContext.
  m->vis.global.offwidth = s.width;
  m->vis.global.offheight = s.height;
  m->vis.quality.offsamples = options_.multisamples;
  m->vis.quality.shadowsize = options_.shadow_map_size;

  s.gl = OSMesaCreateContextExt(OSMESA_RGBA, 24, 8, 8, nullptr);
  if (!s.gl) {
    throw std::runtime_error("cannot create the OSMesa GL context (RGBA, 24-bit depth, 8-bit stencil): is Mesa's "
                             "software renderer (libosmesa6, libgl1-mesa-dri) installed?");
  }
  s.gl_buffer.assign(static_cast<std::size_t>(s.width) * static_cast<std::size_t>(s.height) * 4, 0);
  s.makeCurrent();

  mjv_defaultCamera(&s.camera);
  s.camera.type = mjCAMERA_FREE;
  for (int k = 0; k < 3; ++k) s.camera.lookat[k] = options_.camera.lookat[static_cast<std::size_t>(k)];
  s.camera.distance = options_.camera.distance_m;
  s.camera.azimuth = options_.camera.azimuth_deg;
  s.camera.elevation = options_.camera.elevation_deg;
  mjv_defaultOption(&s.option);

  mjv_defaultScene(&s.scene);
  try {
    mjv_makeScene(m, &s.scene, 2000);
    s.scene_made = true;
    mjr_defaultContext(&s.context);
    mjr_makeContext(m, &s.context, fontScaleFor(s.height));
    s.context_made = true;
  } catch (const sim::MujocoError& e) {
    throw std::runtime_error(std::string("cannot create the MuJoCo render context: ") + e.what());
  }
  if (!s.context.offFBO) throw std::runtime_error("cannot create the MuJoCo render context: no offscreen framebuffer");
  mjr_setBuffer(mjFB_OFFSCREEN, &s.context);
  if (s.context.currentBuffer != mjFB_OFFSCREEN) {
    throw std::runtime_error("the MuJoCo offscreen framebuffer is not available");
  }
  s.scene.flags[mjRND_SHADOW] = options_.shadows ? 1 : 0;
  s.scene.flags[mjRND_REFLECTION] = 0;
  s.scene.flags[mjRND_SKYBOX] = 0;

  s.pixels.resize(static_cast<std::size_t>(s.width) * static_cast<std::size_t>(s.height) * 3);
  s.image.width = s.width;
  s.image.height = s.height;
  s.image.rgb.resize(s.pixels.size());
}

OffscreenRenderer::~OffscreenRenderer() = default;

const Image& OffscreenRenderer::render(const mjModel* m, mjData* d, const Overlay* overlay) {
  Impl& s = *impl_;
  s.makeCurrent();
  mjr_setBuffer(mjFB_OFFSCREEN, &s.context);
  const mjrRect viewport{0, 0, s.width, s.height};
  // The overlay's text gets a band of its own across the top, and the scene the rest: text drawn
  // over the scene would hide the leg wherever the motion takes it.
  const bool text = overlay && (!overlay->text_left.empty() || !overlay->text_right.empty());
  const int band = text ? std::min(s.height / 2, textBandHeight_px(*overlay, s.context.charHeight)) : 0;
  mjv_updateScene(m, d, &s.option, nullptr, &s.camera, mjCAT_ALL, &s.scene);
  mjr_render(mjrRect{0, 0, s.width, s.height - band}, &s.scene, &s.context);

  if (overlay) {
    if (text) {
      mjr_rectangle(mjrRect{0, s.height - band, s.width, band}, 0.05f, 0.06f, 0.08f, 1.0f);
      mjr_overlay(mjFONT_NORMAL, mjGRID_TOPRIGHT, viewport, overlay->text_left.c_str(), overlay->text_right.c_str(),
                  &s.context);
    }
    const int n = static_cast<int>(overlay->panels.size());
    while (static_cast<int>(s.figures.size()) < n) {
      auto f = std::make_unique<mjvFigure>();
      mjv_defaultFigure(f.get());
      s.figures.push_back(std::move(f));
    }
    // Panels stacked in the lower right corner, below the text's band (a chain's many joints
    // make both taller), first panel on top.
    const int pw = s.width * 45 / 100;
    const int ph = n > 0 ? std::min({s.height * 28 / 100, s.height * 80 / 100 / n, (s.height - band) / n}) : 0;
    for (int i = 0; i < n; ++i) {
      const PlotPanel& p = overlay->panels[static_cast<std::size_t>(i)];
      mjvFigure& f = *s.figures[static_cast<std::size_t>(i)];
      f.flg_legend = 0;  // the legend would hide the newest samples; the text names the colors
      f.flg_extend = 0;
      f.flg_ticklabel[0] = 1;
      f.flg_ticklabel[1] = 1;
      f.gridsize[0] = 5;
      f.gridsize[1] = 5;
      f.linewidth = 1.5f;
      const float figure_rgba[4] = {0.05f, 0.06f, 0.08f, 0.80f};
      const float pane_rgba[4] = {0.10f, 0.11f, 0.14f, 0.85f};
      const float legend_rgba[4] = {0.05f, 0.06f, 0.08f, 0.6f};
      std::memcpy(f.figurergba, figure_rgba, sizeof figure_rgba);
      std::memcpy(f.panergba, pane_rgba, sizeof pane_rgba);
      std::memcpy(f.legendrgba, legend_rgba, sizeof legend_rgba);
      f.range[0][0] = static_cast<float>(p.x_range[0]);
      f.range[0][1] = static_cast<float>(p.x_range[1]);
      f.range[1][0] = static_cast<float>(p.y_range[0]);
      f.range[1][1] = static_cast<float>(p.y_range[1]);
      copyText(f.xformat, sizeof f.xformat, "%.1f");
      copyText(f.yformat, sizeof f.yformat, "%.0f");
      copyText(f.minwidth, sizeof f.minwidth, "-000");
      copyText(f.title, sizeof f.title, p.title);
      copyText(f.xlabel, sizeof f.xlabel, "");
      for (int l = 0; l < mjMAXLINE; ++l) f.linepnt[l] = 0;
      const int lines = std::min<int>(static_cast<int>(p.lines.size()), mjMAXLINE);
      for (int l = 0; l < lines; ++l) {
        const PlotLine& line = p.lines[static_cast<std::size_t>(l)];
        const int pts = std::min<int>(static_cast<int>(std::min(line.x.size(), line.y.size())), mjMAXLINEPNT);
        for (int k = 0; k < pts; ++k) {
          f.linedata[l][2 * k] = line.x[static_cast<std::size_t>(k)];
          f.linedata[l][2 * k + 1] = line.y[static_cast<std::size_t>(k)];
        }
        f.linepnt[l] = pts;
        for (int c = 0; c < 3; ++c) f.linergb[l][c] = line.rgb[static_cast<std::size_t>(c)];
        copyText(f.linename[l], sizeof f.linename[l], line.name);
      }
      const mjrRect rect{s.width - pw, (n - 1 - i) * ph, pw, ph};
      mjr_figure(rect, &f, &s.context);
    }
  }

  mjr_readPixels(s.pixels.data(), nullptr, viewport, &s.context);
  const std::size_t row = static_cast<std::size_t>(s.width) * 3;
  for (int y = 0; y < s.height; ++y) {
    std::memcpy(s.image.rgb.data() + static_cast<std::size_t>(y) * row,
                s.pixels.data() + static_cast<std::size_t>(s.height - 1 - y) * row, row);
  }
  return s.image;
}

}  // namespace exoid::render
