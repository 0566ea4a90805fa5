// The viewer's page in headless Chromium (Debian's `chromium`): it loads, a frame arrives,
// a mouse drag moves the camera, the balancer switch (to uniform) takes effect and the
// overlay shows one colour per device, the frame is scaled to fit the window (the page's
// ?selftest=1 mode does what a user would and reports in its title); a screenshot is written.
// The same for view --ar (?selftest=ar).
// Skipped with a message where Chromium is absent.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "support/run_cli.h"
#include "viewer_process.h"

namespace browser_test {

std::string chromium() {
  for (const char* p : {"/usr/bin/chromium", "/usr/bin/chromium-browser"})
    if (std::filesystem::exists(p)) return p;
  return "";
}

TEST(ViewerBrowser, PageLoadsStreamsAndResponds) {
  const std::string browser = chromium();
  if (browser.empty()) GTEST_SKIP() << "Chromium is not installed (apt-get install chromium)";
  multiray::testing::ViewerProcess viewer(
      "--res 96x54 --spp 1 --bounces 2 --devices cpu:threads=1,cpu:threads=1");
  ASSERT_GT(viewer.port(), 0);
  const std::string url = "http://127.0.0.1:" + std::to_string(viewer.port()) + "/";
  // The page holds the browser's virtual clock with a pending request while it tests
  // itself (and with hold=N); the budget is page time beyond that.
  const std::string flags =
      "--headless=new --no-sandbox --disable-gpu --virtual-time-budget=20000 ";
  const auto r =
      multiray::testing::run_cli(browser, flags + "--dump-dom '" + url + "?selftest=1'");
  EXPECT_THAT(r.out, ::testing::HasSubstr("selftest frame=1 drag=1 balancer=1 colors=2 fits=1"))
      << r.out.substr(0, 2000);
  const std::string shot = ::testing::TempDir() + "/viewer.png";
  std::filesystem::remove(shot);
  // hold=3: the page keeps a request open until three frames were shown, so the picture
  // has a frame under the overlay (the empty page compresses to about 16 KB).
  // Chromium on a loaded machine has exited without a screenshot (once in a fresh-clone
  // run beside a long simulation; the same clone passed in 18 s when quiet): a second
  // attempt, not a weaker check, so the picture must still be written.
  for (int attempt = 0; attempt < 2 && !std::filesystem::exists(shot); ++attempt)
    multiray::testing::run_cli(browser, flags + "--window-size=1100,650 --screenshot=" + shot +
                                            " '" + url + "?overlay=1&hold=3'");
  ASSERT_TRUE(std::filesystem::exists(shot));
  EXPECT_GT(std::filesystem::file_size(shot), 30000u);
  EXPECT_EQ(viewer.stop(), 128 + SIGINT);
}

// view --ar with Chromium's fake camera (an animated test picture) and synthetic
// orientation events: the page shows the camera with the rendered objects over it (camera
// pixels where the frame is transparent, the frame's where it is opaque), and turning the
// "device" moves the view; a screenshot shows it.
TEST(ViewerBrowser, ArPageShowsTheCameraUnderTheObjectsAndTurnsWithTheDevice) {
  const std::string browser = chromium();
  if (browser.empty()) GTEST_SKIP() << "Chromium is not installed (apt-get install chromium)";
  multiray::testing::ViewerProcess viewer(std::string("'") + MULTIRAY_SOURCE_DIR +
                                          "/examples/ar/objects.obj' --ground y=0 --ar "
                                          "--env 0.3 --sun 40,35 --res 96x72 --spp 1 "
                                          "--devices cpu:threads=1,cpu:threads=1");
  ASSERT_GT(viewer.port(), 0);
  const std::string url = "http://127.0.0.1:" + std::to_string(viewer.port()) + "/";
  const std::string flags =
      "--headless=new --no-sandbox --disable-gpu --virtual-time-budget=20000 "
      "--use-fake-device-for-media-stream --use-fake-ui-for-media-stream ";
  const auto r =
      multiray::testing::run_cli(browser, flags + "--dump-dom '" + url + "?selftest=ar'");
  EXPECT_THAT(r.out, ::testing::HasSubstr("selftest frame=1 camera=1 over=1 moved=1"))
      << r.out.substr(0, 2000);
  const std::string shot = ::testing::TempDir() + "/viewer_ar.png";
  std::filesystem::remove(shot);
  for (int attempt = 0; attempt < 2 && !std::filesystem::exists(shot); ++attempt)
    multiray::testing::run_cli(browser, flags + "--window-size=900,500 --screenshot=" + shot +
                                            " '" + url + "?ar=1&hold=20'");
  EXPECT_TRUE(std::filesystem::exists(shot));
  EXPECT_EQ(viewer.stop(), 128 + SIGINT);
}

}  // namespace browser_test
