// The image module (image_module.hpp): OpenImageIO behind a C interface, built as houle_image_io.so.
#include <OpenImageIO/imageio.h>

#include <unistd.h>

#include <cstdio>
#include <span>
#include <string>
#include <vector>

#include "image_module.hpp"

namespace {

int fail(const std::string& message, char* error, std::size_t error_size) {
  if (error_size > 0) std::snprintf(error, error_size, "%s", message.c_str());
  return 1;
}

// Lines joined with "; " (OpenImageIO's PNG errors come as three lines, each a step back from the cause).
std::string one_line(const std::string& text) {
  std::string out;
  for (const char c : text) out += c == '\n' ? std::string("; ") : std::string(1, c);
  while (out.size() >= 2 && out.compare(out.size() - 2, 2, "; ") == 0) out.resize(out.size() - 2);
  return out;
}

// libpng and OpenImageIO's PNG reader print their complaints on standard error besides returning
// an error, and a scene's error is one line with its file, line and key: what they print while an
// image is read is caught here, folded into the error if the read fails, passed on if it does not.
class StderrCatch {
 public:
  StderrCatch() : file_(std::tmpfile()) {
    std::fflush(stderr);
    saved_ = file_ ? ::dup(2) : -1;
    if (saved_ >= 0 && ::dup2(::fileno(file_), 2) < 0) {
      ::close(saved_);
      saved_ = -1;
    }
  }
  StderrCatch(const StderrCatch&) = delete;
  StderrCatch& operator=(const StderrCatch&) = delete;
  ~StderrCatch() {
    const std::string text = release();
    if (!text.empty()) std::fprintf(stderr, "%s\n", text.c_str());
  }

  // What was printed, one line; standard error restored. Later calls return "".
  std::string release() {
    std::string text;
    if (saved_ >= 0) {
      std::fflush(stderr);
      ::dup2(saved_, 2);
      ::close(saved_);
      saved_ = -1;
      std::rewind(file_);
      for (int c; (c = std::fgetc(file_)) != EOF;) text += char(c);
      text = one_line(text);
    }
    if (file_) std::fclose(file_);
    file_ = nullptr;
    return text;
  }

 private:
  std::FILE* file_ = nullptr;
  int saved_ = -1;
};

// The reader's reason, else what its library printed, else what a read that stops early means.
std::string reason(const std::string& reported, StderrCatch& printed) {
  const std::string text = printed.release();
  if (!reported.empty()) return one_line(reported);
  if (!text.empty()) return text;
  return "the file ends before its last pixel, or its data are damaged";
}

int can_write(const char* name, char* error, std::size_t error_size) {
  if (OIIO::ImageOutput::create(name)) return 0;
  return fail(OIIO::geterror(), error, error_size);
}

OIIO::TypeDesc type_of(int storage) {
  return storage == houle::cli::linear_half    ? OIIO::TypeDesc::HALF
         : storage == houle::cli::linear_float ? OIIO::TypeDesc::FLOAT
                                               : OIIO::TypeDesc::UINT8;
}

int write_image(const char* path, const char* format_name, const houle::cli::ImageLayout* layout, const void* pixels,
                const houle::cli::ImageAttribute* attributes, int attribute_count, char* error, std::size_t error_size) {
  using houle::cli::ImageAttribute;
  const bool bytes = layout->storage[0] == houle::cli::srgb8;
  OIIO::ImageSpec spec(layout->width, layout->height, layout->channels, type_of(layout->storage[0]));
  spec.channelnames.assign(layout->names, layout->names + layout->channels);
  bool mixed = false;
  for (int c = 0; c < layout->channels; ++c) {
    mixed = mixed || layout->storage[c] != layout->storage[0];
    if (spec.channelnames[std::size_t(c)] == "A") spec.alpha_channel = c;
    if (spec.channelnames[std::size_t(c)] == "Z") spec.z_channel = c;
  }
  if (mixed) {  // EXR: e.g. half colour beside a float Z
    for (int c = 0; c < layout->channels; ++c) spec.channelformats.push_back(type_of(layout->storage[c]));
  }
  // zlib level 1: PNG writing dominated frame time at the default 6 (docs/design.md 11: 45 vs 14 ms).
  spec.attribute("png:compressionLevel", 1);
  spec.attribute("oiio:ColorSpace", bytes ? "sRGB" : "Linear");
  // Without a DateTime OpenImageIO stamps the time of writing, and two renders of a frame differ.
  spec.attribute("DateTime", "");
  for (const ImageAttribute& a : std::span(attributes, std::size_t(attribute_count))) {
    switch (a.type) {
      case ImageAttribute::text: spec.attribute(a.name, a.string); break;
      case ImageAttribute::integer: spec.attribute(a.name, a.ints[0]); break;
      case ImageAttribute::real: spec.attribute(a.name, OIIO::TypeDesc::DOUBLE, &a.number); break;
      case ImageAttribute::matrix44: spec.attribute(a.name, OIIO::TypeDesc::TypeMatrix44, a.floats); break;
      case ImageAttribute::rational: spec.attribute(a.name, OIIO::TypeDesc::TypeRational, a.ints); break;
    }
  }
  auto out = OIIO::ImageOutput::create(format_name);
  if (!out) return fail(OIIO::geterror(), error, error_size);
  bool ok = out->open(path, spec) && out->write_image(bytes ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT, pixels);
  ok = out->close() && ok;
  return ok ? 0 : fail(out->geterror(), error, error_size);
}

int read_first_channel(const char* path, void* context, float* (*allocate)(void*, int, int), char* error,
                       std::size_t error_size) {
  StderrCatch printed;
  auto in = OIIO::ImageInput::open(path);
  if (!in) return fail("cannot open the image: " + reason(OIIO::geterror(), printed), error, error_size);
  const OIIO::ImageSpec& spec = in->spec();
  float* dst = allocate(context, spec.width, spec.height);
  if (!dst) return 2;
  std::vector<float> pixels(std::size_t(spec.width) * std::size_t(spec.height) * std::size_t(spec.nchannels));
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data())) {
    const std::string reported = in->geterror();
    in.reset();  // its library may print more as it closes
    return fail("cannot read the image: " + reason(reported, printed), error, error_size);
  }
  for (std::size_t i = 0, n = std::size_t(spec.width) * std::size_t(spec.height); i < n; ++i) {
    dst[i] = pixels[i * std::size_t(spec.nchannels)];
  }
  return 0;
}

constexpr houle::cli::ImageModule module{can_write, write_image, read_first_channel};

}  // namespace

extern "C" __attribute__((visibility("default"))) const houle::cli::ImageModule* houle_image_module() {
  return &module;
}
