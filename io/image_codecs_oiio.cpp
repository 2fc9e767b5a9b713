// The image module: lhr's only OpenImageIO calls, built as a shared module
// that io/image_codecs.cpp loads on first use (docs/design.md §5, "Images on
// demand").

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <string>
#include <vector>

#include "io/image_codecs.hpp"

namespace {

using lhr::image_codecs::DecodedImage;
using lhr::image_codecs::DecodeFailure;
using lhr::image_codecs::EncodeRequest;

// A failure is never reported as an empty message: the caller tells success by it.
std::string failed(std::string message, const char* otherwise) {
  return message.empty() ? std::string(otherwise) : message;
}

std::string encode(const EncodeRequest& request, std::vector<unsigned char>& encoded) {
  encoded.clear();
  OIIO::Filesystem::IOVecOutput proxy(encoded);
  auto out = OIIO::ImageOutput::create(request.path);
  if (!out) return failed(OIIO::geterror(), "no image writer for this file type");
  if (!out->supports("ioproxy") || !out->set_ioproxy(&proxy)) return "the image writer cannot write to memory";
  OIIO::ImageSpec spec(request.width, request.height, 3, request.png ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT);
  if (!request.software.empty()) spec.attribute("Software", request.software);
  for (const auto& [key, value] : request.notes) spec.attribute(key, value);
  if (request.has_camera && !request.png) {
    spec.attribute("worldtocamera", OIIO::TypeMatrix, request.world_to_camera.data());
    spec.attribute("worldtoscreen", OIIO::TypeMatrix, request.world_to_ndc.data());
  }
  if (!out->open(request.path, spec)) return failed(out->geterror(), "the image writer cannot open it");
  const std::size_t values = 3 * static_cast<std::size_t>(request.width) * request.height;
  bool ok;
  if (request.png) {
    std::vector<float> clamped(request.rgb, request.rgb + values);
    for (float& v : clamped) v = std::clamp(v, 0.0f, 1.0f);
    ok = out->write_image(OIIO::TypeDesc::FLOAT, clamped.data());
  } else {
    ok = out->write_image(OIIO::TypeDesc::FLOAT, request.rgb);
  }
  if (!ok || !out->close()) return failed(out->geterror(), "the image writer failed");
  return {};
}

std::string decode(const std::string& path, DecodedImage& image, DecodeFailure& failure) {
  failure = DecodeFailure::kOpen;
  auto in = OIIO::ImageInput::open(path);
  if (!in) return failed(OIIO::geterror(), "not an image file lhr can read");
  const OIIO::ImageSpec& spec = in->spec();
  image.width = spec.width;
  image.height = spec.height;
  image.channels = spec.nchannels;
  image.floating_point = spec.format.is_floating_point();
  image.colour_space = spec.get_string_attribute("oiio:ColorSpace");
  image.pixels.clear();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) {
    failure = DecodeFailure::kNone;  // the caller says what an empty image means to it
    return {};
  }
  image.pixels.resize(static_cast<std::size_t>(spec.width) * spec.height * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data())) {
    failure = DecodeFailure::kPixels;
    return failed(in->geterror(), "the pixels cannot be read");
  }
  failure = DecodeFailure::kNone;
  return {};
}

const lhr::image_codecs::Table kTable{lhr::image_codecs::kAbiVersion, &encode, &decode};

}  // namespace

extern "C" __attribute__((visibility("default"))) const lhr::image_codecs::Table* lhr_image_codecs_table() {
  return &kTable;
}
