// Where rendered frames go: an image sequence through OpenImageIO, or raw framebuffers to a file or
// a pipe. Writers report errors as messages naming the file; a reader closing the pipe is not an
// error but the end of the run.
#pragma once
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "houle/runtime/expected.hpp"
#include "houle/render/framebuffer.hpp"
#include "houle/surface/camera.hpp"
#include "y4m.hpp"

namespace houle::cli {

enum class WriteStatus { ok, closed, failed };

class FrameWriter {
 public:
  virtual ~FrameWriter() = default;
  /// Writes frame number `index`; on `failed`, error() says why.
  virtual WriteStatus write(const Framebuffer& fb, const ToneMap& tm, long index) = 0;
  /// After the last frame: a file written under a temporary name gets its final name.
  virtual WriteStatus finish() { return WriteStatus::ok; }
  const std::string& error() const { return error_; }

 protected:
  std::string error_;
};

/// Whether frames can go there, checked before the scene is built (seconds, for a large one) and
/// without creating anything: the pattern names an image format (and a float one where `float32`),
/// and its folder, or the nearest existing folder above it, is writable; for raw, the file's folder
/// exists and the folder and the file are writable.
Expected<void> check_image_output(const std::string& pattern, bool float32);
Expected<void> check_raw_output(const std::string& path);

/// What image files say of their frames beyond the pixels. EXR holds all of it, other formats what
/// they can: the camera as OpenEXR's worldToCamera and worldToNDC, framesPerSecond, Software (houle
/// and its version), houle:frame (the frame number) and houle:time (s of scene time, frame / fps);
/// with `aovs`, the channels A, Z (32-bit float), N.X, N.Y, N.Z and sea (framebuffer.hpp says what
/// each holds). No date: two renders of a frame are the same bytes.
struct ImageHeader {
  double fps = 30.0;
  Camera camera;
  FrameAovs aovs;
};

/// `pattern` holds one printf integer conversion (e.g. "frames/%04d.png"); the extension, in any
/// case, picks the format: linear half floats for EXR, linear 32-bit floats for HDR, 8-bit
/// sRGB for PNG/JPEG/TIFF and the rest. `float32` asks for linear 32-bit floats: EXR in full float,
/// TIFF as float (an error for 8-bit-only formats). Each image is written under
/// a temporary name and renamed, so no partial image ever has the final name. The pattern's folder
/// is made, with its parents, if missing.
Expected<std::unique_ptr<FrameWriter>> make_image_writer(const std::string& pattern, int width, int height,
                                                         bool float32, const ImageHeader& header);

/// Tightly packed frames of `format` to `path`, or to standard output for "-". When `whole`, the
/// frames go to a temporary file that finish() renames to `path` (a writer destroyed before that
/// removes it): `path` exists only with every frame in it.
Expected<std::unique_ptr<FrameWriter>> make_raw_writer(const std::string& path, PixelFormat format, int width,
                                                       int height, bool whole = false);

/// A YUV4MPEG2 stream (y4m.hpp) to `path` or standard output ("-"), as make_raw_writer writes raw frames.
Expected<std::unique_ptr<FrameWriter>> make_y4m_writer(const std::string& path, int width, int height, double fps,
                                                       Y4mChroma chroma, bool whole = false);

/// "frames/%04d.png" with 7 -> "frames/0007.png"; an error if the pattern has not exactly one
/// integer conversion (and no other conversions).
Expected<std::string> format_frame_name(const std::string& pattern, long index);

}  // namespace houle::cli
