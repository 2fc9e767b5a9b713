#include "io/image_io.hpp"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cctype>
#include <stdexcept>
#include <string>

#include "io/atomic_file.hpp"
#include "io/input_error.hpp"

namespace lhr {

namespace {

std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

}  // namespace

void write_image(const std::filesystem::path& path, const Image& image) {
  AtomicOutputs outputs;
  write_image(outputs, path, image);
  outputs.publish();
}

void write_image(AtomicOutputs& outputs, const std::filesystem::path& path, const Image& image) {
  const std::string ext = lower_extension(path);
  if (ext != ".png" && ext != ".exr") {
    throw std::runtime_error(path.string() + ": unknown image type (use .png or .exr)");
  }
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != 3 * static_cast<std::size_t>(image.width) * image.height) {
    throw std::runtime_error(path.string() + ": image has no pixels or a wrong buffer size");
  }
  // Encoded in memory, then written through the library's checked stream:
  // the file writers of the image plugins do not all report a failed write
  // or close with its reason.
  std::vector<unsigned char> encoded;
  {
    OIIO::Filesystem::IOVecOutput proxy(encoded);
    auto out = OIIO::ImageOutput::create(path.string());
    if (!out) throw std::runtime_error(path.string() + ": " + OIIO::geterror());
    if (!out->supports("ioproxy") || !out->set_ioproxy(&proxy)) {
      throw std::runtime_error(path.string() + ": the image writer cannot write to memory");
    }
    const bool png = ext == ".png";
    OIIO::ImageSpec spec(image.width, image.height, 3, png ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::HALF);
    if (!out->open(path.string(), spec)) throw std::runtime_error(path.string() + ": " + out->geterror());
    bool ok;
    if (png) {
      std::vector<float> clamped(image.rgb.size());
      std::transform(image.rgb.begin(), image.rgb.end(), clamped.begin(),
                     [](float v) { return std::clamp(v, 0.0f, 1.0f); });
      ok = out->write_image(OIIO::TypeDesc::FLOAT, clamped.data());
    } else {
      ok = out->write_image(OIIO::TypeDesc::FLOAT, image.rgb.data());
    }
    if (!ok || !out->close()) throw std::runtime_error(path.string() + ": " + out->geterror());
  }
  outputs.stage(path, [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(encoded.data()), static_cast<std::streamsize>(encoded.size()));
  });
}

Image read_image(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path)) throw InputError(path, "no such file");
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) throw InputError(path, "cannot read image: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) throw InputError(path, "image has no pixels");
  std::vector<float> all(static_cast<std::size_t>(spec.width) * spec.height * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, all.data())) {
    throw InputError(path, "cannot read pixels: " + in->geterror());
  }
  Image image(spec.width, spec.height);
  for (std::size_t i = 0; i < static_cast<std::size_t>(spec.width) * spec.height; ++i) {
    for (int k = 0; k < 3; ++k) image.rgb[3 * i + k] = all[i * spec.nchannels + std::min(k, spec.nchannels - 1)];
  }
  return image;
}

}  // namespace lhr
