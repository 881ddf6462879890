// Image files given to compare, upsample and blend go through the input guard (core/image_io.h,
// core/input_file.h): a PNG whose header claims 30000x30000 or 65535x65535 pixels on a file of a few
// dozen bytes is refused from its header, before a pixel is allocated (it ended in an allocation
// failure, exit 1), and a FIFO or a link to /dev/zero is refused without a byte read (a FIFO hung
// the command). Exit code 2, one line naming the file. Each command runs under a timeout, so a
// regression fails instead of hanging the tests.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>

#include "core/image_io.h"
#include "tests/app/cli_test_support.h"

namespace {

namespace fs = std::filesystem;

using fovlab::cli_test::CommandResult;
using fovlab::cli_test::expect_one_line_error;

fs::path scratch() { return fovlab::cli_test::scratch("fovlab-image-input-cli-test"); }

CommandResult run_bounded(const std::string& arguments) { return fovlab::cli_test::run_in(scratch(), arguments, 120); }

// PNG's CRC-32 (ISO 3309, the reflected polynomial 0xEDB88320) of a chunk's type and data.
uint32_t png_crc(const std::string& bytes) {
  uint32_t crc = 0xFFFFFFFFu;
  for (unsigned char byte : bytes) {
    crc ^= byte;
    for (int bit = 0; bit < 8; ++bit) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return crc ^ 0xFFFFFFFFu;
}

std::string big_endian(uint32_t value) {
  return {char(value >> 24), char((value >> 16) & 0xFF), char((value >> 8) & 0xFF), char(value & 0xFF)};
}

std::string png_chunk(const std::string& type, const std::string& data) {
  return big_endian(uint32_t(data.size())) + type + data + big_endian(png_crc(type + data));
}

// A valid PNG header (8-bit RGBA, correct CRCs) claiming width x height pixels, then an empty zlib
// stream and the end: a few dozen bytes.
std::string png_header_bomb(uint32_t width, uint32_t height) {
  const std::string signature = "\x89PNG\r\n\x1a\n";
  const std::string header = big_endian(width) + big_endian(height) + std::string("\x08\x06\x00\x00\x00", 5);
  const std::string empty_zlib("\x78\x9c\x03\x00\x00\x00\x00\x01", 8);
  return signature + png_chunk("IHDR", header) + png_chunk("IDAT", empty_zlib) + png_chunk("IEND", "");
}

TEST(ImageInputCli, HeaderBombsAreRefusedFromTheHeaderBeforeAllocating) {
  const fs::path small = scratch() / "small.png";
  fovlab::write_image(small, fovlab::Image(8, 8, 3));
  const fs::path out = scratch() / "never.exr";
  for (const auto& [width, height] : std::array<std::pair<uint32_t, uint32_t>, 2>{{{30000, 30000}, {65535, 65535}}}) {
    const std::string size = std::to_string(width) + "x" + std::to_string(height);
    SCOPED_TRACE(size);
    const fs::path bomb =
        fovlab::cli_test::write_file(scratch() / ("bomb-" + size + ".png"), png_header_bomb(width, height));
    ASSERT_LT(fs::file_size(bomb), 100u);
    const std::string expected =
        bomb.string() + ": " + size + " pixels in its header: expected 1 to 16384 pixels a side";
    expect_one_line_error(run_bounded("compare " + bomb.string() + " " + small.string()), expected);
    expect_one_line_error(run_bounded("compare " + small.string() + " " + bomb.string()), expected);
    expect_one_line_error(run_bounded("upsample " + bomb.string() + " --factor 2 --out " + out.string()), expected);
    expect_one_line_error(
        run_bounded("blend --frame " + bomb.string() + " --gaze 5,5 --foveal-deg 10 --out " + out.string()), expected);
  }
  EXPECT_FALSE(fs::exists(out));
}

TEST(ImageInputCli, AFifoOrALinkToADeviceIsRefusedWithoutReadingIt) {
  const fs::path small = scratch() / "small.png";
  fovlab::write_image(small, fovlab::Image(8, 8, 3));
  const fs::path fifo = scratch() / "fifo.png";
  fs::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  expect_one_line_error(run_bounded("compare " + fifo.string() + " " + small.string()),
                        fifo.string() + ": not a regular file (a FIFO or pipe)");
  const fs::path zero = scratch() / "zero.exr";
  fs::remove(zero);
  fs::create_symlink("/dev/zero", zero);
  expect_one_line_error(
      run_bounded("upsample " + zero.string() + " --factor 2 --out " + (scratch() / "never.exr").string()),
      zero.string() + ": not a regular file (a character device)");
  expect_one_line_error(run_bounded("blend --frame " + zero.string() + " --gaze 5,5 --foveal-deg 10 --out " +
                                    (scratch() / "never.png").string()),
                        zero.string() + ": not a regular file (a character device)");
  EXPECT_FALSE(fs::exists(scratch() / "never.exr"));
}

}  // namespace
