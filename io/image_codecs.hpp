#pragma once
// Image encoding and decoding through OpenImageIO, in a module of its own
// that is loaded the first time an image is read or written (docs/design.md
// §5, "Images on demand"). OpenImageIO links some 250 shared libraries
// (video, DICOM, GIS formats); loading them costs about 0.4 s per process,
// which every command paid before its first line, whether it touched an
// image or not. `lhr mesh`, `lhr validate` and every test that touches no
// image now start at once.

#include <array>
#include <string>
#include <utility>
#include <vector>

namespace lhr::image_codecs {

// What the module is asked to encode: RGB floats, row 0 at the top.
struct EncodeRequest {
  std::string path;  // names the format by its extension, and the file in messages
  int width = 0;
  int height = 0;
  bool png = false;           // 8-bit PNG of values clamped to [0,1]; else 32-bit float EXR
  const float* rgb = nullptr;  // 3 * width * height
  std::string software;
  std::vector<std::pair<std::string, std::string>> notes;
  bool has_camera = false;  // EXR only: worldtocamera and worldtoscreen
  std::array<float, 16> world_to_camera{};
  std::array<float, 16> world_to_ndc{};
};

// A decoded image: every channel as float, interleaved.
struct DecodedImage {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<float> pixels;
  bool floating_point = false;  // stored as float (EXR, HDR) rather than integers
  std::string colour_space;     // OpenImageIO's oiio:ColorSpace
};

enum class DecodeFailure { kNone, kOpen, kPixels };

// The module's entry points. Both return an empty string on success, else a
// message (the library's where it gives one) without the file name.
struct Table {
  int abi_version;
  std::string (*encode)(const EncodeRequest& request, std::vector<unsigned char>& encoded);
  std::string (*decode)(const std::string& path, DecodedImage& image, DecodeFailure& failure);
};

inline constexpr int kAbiVersion = 1;
inline constexpr const char* kEntryPoint = "lhr_image_codecs_table";

// The module's table, loaded on first use (thread-safe). Throws
// std::runtime_error naming every place it looked when the module cannot be
// loaded.
const Table& codecs();

}  // namespace lhr::image_codecs
