#include "io/image_io.hpp"

#include <algorithm>
#include <cmath>
#include <cctype>
#include <stdexcept>
#include <string>

#include "io/atomic_file.hpp"
#include "io/image_codecs.hpp"
#include "io/input_error.hpp"

namespace lhr {

namespace {

std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

}  // namespace

std::array<float, 16> world_to_camera_matrix(const Camera& camera) {
  const Vec3 forward = (camera.target - camera.eye).normalized();
  const Vec3 right = OpenMesh::cross(forward, camera.up).normalized();
  const Vec3 up = OpenMesh::cross(right, forward);
  const Vec3& e = camera.eye;
  std::array<float, 16> m{};
  for (int row = 0; row < 3; ++row) {
    m[4 * row + 0] = static_cast<float>(right[row]);
    m[4 * row + 1] = static_cast<float>(up[row]);
    m[4 * row + 2] = static_cast<float>(forward[row]);
  }
  m[12] = static_cast<float>(-OpenMesh::dot(right, e));
  m[13] = static_cast<float>(-OpenMesh::dot(up, e));
  m[14] = static_cast<float>(-OpenMesh::dot(forward, e));
  m[15] = 1.0f;
  return m;
}

std::array<float, 16> world_to_ndc_matrix(const Camera& camera) {
  // Camera space to NDC: x' = x / (z tan(half width)), y' = y / (z tan(half
  // height)) after dividing by w' = z.
  const double half_height = std::tan(0.5 * camera.fov_y_deg * M_PI / 180.0);
  const double half_width = half_height * camera.width / camera.height;
  const std::array<float, 16> view = world_to_camera_matrix(camera);
  std::array<double, 16> projection{};
  projection[0] = 1.0 / half_width;
  projection[5] = 1.0 / half_height;
  projection[10] = 1.0;
  projection[11] = 1.0;
  std::array<float, 16> m{};
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      double sum = 0.0;
      for (int k = 0; k < 4; ++k) sum += view[4 * r + k] * projection[4 * k + c];
      m[4 * r + c] = static_cast<float>(sum);
    }
  }
  return m;
}

void write_image(const std::filesystem::path& path, const Image& image, const ImageMetadata& metadata) {
  AtomicOutputs outputs;
  write_image(outputs, path, image, metadata);
  outputs.publish();
}

void write_image(AtomicOutputs& outputs, const std::filesystem::path& path, const Image& image,
                 const ImageMetadata& metadata) {
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
  image_codecs::EncodeRequest request;
  request.path = path.string();
  request.width = image.width;
  request.height = image.height;
  request.png = ext == ".png";
  request.rgb = image.rgb.data();
  request.software = metadata.software;
  request.notes = metadata.notes;
  if (metadata.camera) {
    request.has_camera = true;
    request.world_to_camera = world_to_camera_matrix(*metadata.camera);
    request.world_to_ndc = world_to_ndc_matrix(*metadata.camera);
  }
  std::vector<unsigned char> encoded;
  if (const std::string error = image_codecs::codecs().encode(request, encoded); !error.empty()) {
    throw std::runtime_error(path.string() + ": " + error);
  }
  outputs.stage(path, [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(encoded.data()), static_cast<std::streamsize>(encoded.size()));
  });
}

Image read_image(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path)) throw InputError(path, "no such file");
  image_codecs::DecodedImage decoded;
  image_codecs::DecodeFailure failure;
  const std::string error = image_codecs::codecs().decode(path.string(), decoded, failure);
  if (failure == image_codecs::DecodeFailure::kOpen) throw InputError(path, "cannot read image: " + error);
  if (failure == image_codecs::DecodeFailure::kPixels) throw InputError(path, "cannot read pixels: " + error);
  if (decoded.pixels.empty()) throw InputError(path, "image has no pixels");
  Image image(decoded.width, decoded.height);
  const int channels = decoded.channels;
  for (std::size_t i = 0; i < static_cast<std::size_t>(decoded.width) * decoded.height; ++i) {
    for (int k = 0; k < 3; ++k) image.rgb[3 * i + k] = decoded.pixels[i * channels + std::min(k, channels - 1)];
  }
  return image;
}

}  // namespace lhr
