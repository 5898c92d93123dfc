// Contract checks (houle/runtime/assert.hpp) abort with the place and what must hold. Built only with
// HOULE_ASSERTS (the dev, asan, tsan and fuzz presets): without it the checks are compiled out.
#include <gtest/gtest.h>

#include "houle/render/renderer.hpp"
#include "houle/runtime/expected.hpp"
#include "houle/surface/camera.hpp"
#include "houle/surface/surface_frame.hpp"

namespace {

constexpr std::uint32_t W = 16, H = 9;

struct Frame {
  houle::Renderer renderer;
  houle::SurfaceFrame surface;
  houle::Camera camera;
};

Frame make_frame() {
  houle::SurfaceFrameConfig config;
  config.levels = 2;
  config.cells = 32;
  config.tile_cells = 8;
  houle::Expected<houle::SurfaceFrame> surface = houle::SurfaceFrame::create(config);
  houle::CameraParams cp;
  cp.width = W;
  cp.height = H;
  const houle::Expected<houle::Camera> camera = houle::make_camera(cp);
  houle::Expected<houle::Renderer> renderer = houle::Renderer::create(houle::RenderScene{}, W, H, {}, 1);
  EXPECT_TRUE(surface.ok() && camera.ok() && renderer.ok());
  return {std::move(renderer).value(), std::move(surface).value(), camera.value()};
}

class Contracts : public testing::Test {
 protected:
  // Death tests fork; "threadsafe" re-runs the program for each, so no thread of this one is copied.
  void SetUp() override { GTEST_FLAG_SET(death_test_style, "threadsafe"); }
};

TEST_F(Contracts, RenderIntoAFramebufferOfTheWrongSizeAborts) {
  Frame f = make_frame();
  houle::Framebuffer wide(W + 1, H);
  EXPECT_DEATH(f.renderer.render(f.surface, nullptr, nullptr, f.camera, wide),
               "renderer\\.cpp:[0-9]+: houle contract violated: Renderer::render: a framebuffer of the renderer's "
               "width x height");
  houle::Framebuffer empty;
  EXPECT_DEATH(f.renderer.render(f.surface, nullptr, nullptr, f.camera, empty), "a framebuffer of the renderer's");
}

TEST_F(Contracts, RenderWithACameraOfTheWrongSizeAborts) {
  Frame f = make_frame();
  houle::Framebuffer fb(W, H);
  f.camera.height = H + 1;
  EXPECT_DEATH(f.renderer.render(f.surface, nullptr, nullptr, f.camera, fb),
               "Renderer::render: a camera of the renderer's width and height");
}

TEST_F(Contracts, TheValueOfAnErrorAborts) {
  const houle::Expected<int> failed = houle::Error{"n", "a number"};
  EXPECT_DEATH((void)failed.value(), "the value of an Expected that holds an Error");
  const houle::Expected<int> value = 3;
  EXPECT_DEATH((void)value.error(), "the error of an Expected that holds no Error");
  const houle::Expected<void> success{};
  EXPECT_DEATH((void)success.error(), "the error of an Expected that holds no Error");
}

}  // namespace
