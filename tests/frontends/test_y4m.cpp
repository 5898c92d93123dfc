// The y4m stream's conversion (frontends/houle/y4m.hpp): known sRGB codes to BT.709 limited-range
// Y'CbCr, the published values; 4:2:0's chroma as the mean of each 2 x 2 block, odd edges included;
// the header; the frame-rate ratio it shares with EXR headers.
#include <gtest/gtest.h>

#include <array>
#include <cstddef>
#include <vector>

#include "cli.hpp"
#include "y4m.hpp"

namespace {

using houle::cli::Y4mChroma;

std::vector<std::byte> codes(std::initializer_list<std::array<int, 3>> pixels) {
  std::vector<std::byte> out;
  for (const auto& p : pixels) {
    for (int c : p) out.push_back(std::byte(c));
  }
  return out;
}

TEST(Y4m, Bt709LimitedRangeOfKnownColours) {
  // BT.709's 8-bit studio-range values (ITU-R BT.709-6 and every colour-bar generator): black and white
  // at Y' 16 and 235, the primaries, their complements and mid grey.
  struct Case {
    std::array<int, 3> rgb;
    int y, cb, cr;
  };
  const Case cases[] = {{{0, 0, 0}, 16, 128, 128},       {{255, 255, 255}, 235, 128, 128}, {{255, 0, 0}, 63, 102, 240},
                        {{0, 255, 0}, 173, 42, 26},      {{0, 0, 255}, 32, 240, 118},      {{255, 255, 0}, 219, 16, 138},
                        {{0, 255, 255}, 188, 154, 16},   {{255, 0, 255}, 78, 214, 230},    {{128, 128, 128}, 126, 128, 128}};
  std::vector<std::byte> rgb;
  for (const Case& c : cases) {
    for (int v : c.rgb) rgb.push_back(std::byte(v));
  }
  const int n = int(std::size(cases));
  std::vector<std::byte> out(houle::cli::y4m_frame_bytes(n, 1, Y4mChroma::c444));
  ASSERT_EQ(out.size(), std::size_t(3 * n));
  houle::cli::y4m_from_rgb24(rgb, n, 1, Y4mChroma::c444, out);
  for (int i = 0; i < n; ++i) {
    EXPECT_EQ(int(out[std::size_t(i)]), cases[i].y) << i;
    EXPECT_EQ(int(out[std::size_t(n + i)]), cases[i].cb) << i;
    EXPECT_EQ(int(out[std::size_t(2 * n + i)]), cases[i].cr) << i;
  }
}

TEST(Y4m, Chroma420IsTheMeanOfEachBlockOddEdgesIncluded) {
  // 3 x 3: blocks of 2 x 2, 1 x 2, 2 x 1 and 1 x 1 pixels. Red and blue mixed half and half give the
  // mean of their Cb (102 and 240: 171) and Cr (240 and 118: 179).
  const std::vector<std::byte> rgb = codes({{255, 0, 0}, {0, 0, 255}, {0, 0, 255},  //
                                            {0, 0, 255}, {255, 0, 0}, {255, 0, 0},  //
                                            {255, 0, 0}, {255, 0, 0}, {0, 0, 0}});
  std::vector<std::byte> out(houle::cli::y4m_frame_bytes(3, 3, Y4mChroma::c420));
  ASSERT_EQ(out.size(), std::size_t(9 + 2 * 4));
  houle::cli::y4m_from_rgb24(rgb, 3, 3, Y4mChroma::c420, out);
  const int y[9] = {63, 32, 32, 32, 63, 63, 63, 63, 16};
  for (int i = 0; i < 9; ++i) EXPECT_EQ(int(out[std::size_t(i)]), y[i]) << i;
  // (102 + 240) / 2 = 171 exactly; Cr (240 + 118) / 2 = 179. A lone red pixel keeps its own chroma.
  const int cb[4] = {171, 171, 102, 128}, cr[4] = {179, 179, 240, 128};
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(int(out[std::size_t(9 + i)]), cb[i]) << i;
    EXPECT_EQ(int(out[std::size_t(13 + i)]), cr[i]) << i;
  }
}

TEST(Y4m, HeaderStatesSizeRateChromaAndRange) {
  EXPECT_EQ(houle::cli::y4m_header(640, 360, 30.0, Y4mChroma::c420), "YUV4MPEG2 W640 H360 F30:1 Ip A1:1 C420jpeg XCOLORRANGE=LIMITED\n");
  EXPECT_EQ(houle::cli::y4m_header(3, 2, 29.97, Y4mChroma::c444), "YUV4MPEG2 W3 H2 F30000:1001 Ip A1:1 C444 XCOLORRANGE=LIMITED\n");
  // ffmpeg refuses a header line of 96 bytes or more ("Header too large"): the longest houle can write.
  const std::string longest = houle::cli::y4m_header(16384, 16384, 987.654321, Y4mChroma::c420);
  EXPECT_EQ(longest, "YUV4MPEG2 W16384 H16384 F987654321:1000000 Ip A1:1 C420jpeg XCOLORRANGE=LIMITED\n");
  EXPECT_LT(longest.size(), 96u);
}

TEST(Y4m, FrameRateRatios) {
  using houle::cli::frame_rate_ratio;
  EXPECT_EQ(frame_rate_ratio(30.0), std::make_pair(30, 1));
  EXPECT_EQ(frame_rate_ratio(1000.0), std::make_pair(1000, 1));
  EXPECT_EQ(frame_rate_ratio(24000.0 / 1001.0), std::make_pair(24000, 1001));
  EXPECT_EQ(frame_rate_ratio(59.94), std::make_pair(60000, 1001));
  EXPECT_EQ(frame_rate_ratio(12.5), std::make_pair(25, 2));
  EXPECT_EQ(frame_rate_ratio(0.1), std::make_pair(1, 10));
  EXPECT_EQ(frame_rate_ratio(1e-9), std::make_pair(1, 1000000));  // the smallest the ratio holds
}

}  // namespace
