// The image module (io/image_codecs.hpp): OpenImageIO comes into a process
// only when an image is read or written, and a module that cannot be found
// or loaded is a one-line error naming it.

#include <gtest/gtest.h>

#include <link.h>

#include <cstdlib>
#include <string>

#include "io/image_io.hpp"
#include "io/scene_loader.hpp"
#include "test_support.hpp"

namespace lhr {
namespace {

bool open_image_io_in_process() {
  bool found = false;
  dl_iterate_phdr(
      [](dl_phdr_info* info, std::size_t, void* data) {
        if (info->dlpi_name && std::string(info->dlpi_name).find("libOpenImageIO") != std::string::npos) {
          *static_cast<bool*>(data) = true;
        }
        return 0;
      },
      &found);
  return found;
}

// One test, since the process's state is what it checks.
TEST(ImageCodecs, OpenImageIOIsLoadedOnlyWhenAnImageIsFirstWrittenOrRead) {
  ASSERT_FALSE(open_image_io_in_process()) << "linked at start: every process pays for its libraries";
  const LoadResult loaded = load_scene(test::source_dir() / "data/cornell/cornell.scene.json");
  EXPECT_FALSE(loaded.scene.surfaces.empty());
  EXPECT_FALSE(open_image_io_in_process()) << "loading a scene without textures needs no image library";

  const auto dir = test::fresh_dir("image_codecs_on_demand");
  Image image(5, 3);
  for (std::size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] = 0.125f * static_cast<float>(i % 7);
  write_image(dir / "a.exr", image);
  EXPECT_TRUE(open_image_io_in_process());
  const Image back = read_image(dir / "a.exr");
  ASSERT_EQ(back.width, 5);
  ASSERT_EQ(back.height, 3);
  EXPECT_EQ(back.rgb, image.rgb);
}

class ScopedEnvironment {
 public:
  ScopedEnvironment(const char* name, const std::string& value) : name_(name) { setenv(name, value.c_str(), 1); }
  ~ScopedEnvironment() { unsetenv(name_); }
  ScopedEnvironment(const ScopedEnvironment&) = delete;
  ScopedEnvironment& operator=(const ScopedEnvironment&) = delete;

 private:
  const char* name_;
};

TEST(ImageCodecs, AModuleThatIsMissingOrNotAModuleIsOneLineNamingIt) {
  const auto dir = test::fresh_dir("image_codecs_missing");
  Image image(2, 2);
  for (float& v : image.rgb) v = 0.5f;
  write_image(dir / "a.exr", image);
  test::write_text(dir / "not-a-module.so", "plain text\n");
  {
    const ScopedEnvironment env("LHR_IMAGE_CODECS", (dir / "nowhere.so").string());
    const test::CommandResult r = test::run_lhr({"compare", (dir / "a.exr").string(), (dir / "a.exr").string()});
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("cannot find lhr's image module"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find((dir / "nowhere.so").string()), std::string::npos) << r.err;
  }
  {
    const ScopedEnvironment env("LHR_IMAGE_CODECS", (dir / "not-a-module.so").string());
    const test::CommandResult r = test::run_lhr({"compare", (dir / "a.exr").string(), (dir / "a.exr").string()});
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find((dir / "not-a-module.so").string() + ": cannot load the image module"), std::string::npos)
        << r.err;
  }
  // Without the variable the module beside the build or the installed binary is found.
  const test::CommandResult r = test::run_lhr({"compare", (dir / "a.exr").string(), (dir / "a.exr").string()});
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

}  // namespace
}  // namespace lhr
