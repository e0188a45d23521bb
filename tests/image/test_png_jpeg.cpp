// The image module's own PNG and JPEG codecs against OpenCV's (what the plugin runs: imdecode with
// IMREAD_UNCHANGED, imread with IMREAD_GRAYSCALE): the same Mat, type and pixels, for every kind of PNG and
// JPEG, written by OpenCV, by a PNG writer of this file's own and by the module's encoders.
#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <string>
#include <vector>

#include "../../src/image/png_jpeg.hpp"
#include "common/temp_dir.hpp"
#include "seqtopo/image/codecs.hpp"

namespace seqtopo::image {
namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<std::uint8_t>;
using codecs::direct::Mode;
using codecs::direct::Outcome;

std::string same(const cv::Mat& a, const cv::Mat& b) {
  if (a.empty() != b.empty()) return a.empty() ? "ours is empty" : "OpenCV's is empty";
  if (a.empty()) return "";
  if (a.type() != b.type()) return "type " + std::to_string(a.type()) + " != " + std::to_string(b.type());
  if (a.size() != b.size()) return "size differs";
  if (cv::norm(a, b, cv::NORM_INF) != 0) return "pixels differ";
  return "";
}

// Ours equals OpenCV's for the bytes, as stored and as grey (an unhandled variant is the plugin's: skipped).
void expect_as_opencv(const Bytes& bytes, const std::string& what, bool must_handle = true) {
  const cv::Mat buffer(1, static_cast<int>(bytes.size()), CV_8U, const_cast<std::uint8_t*>(bytes.data()));
  for (const Mode mode : {Mode::unchanged, Mode::grey}) {
    cv::Mat ours;
    const Outcome outcome = codecs::direct::decode(bytes, mode, ours);
    if (must_handle) {
      EXPECT_EQ(outcome, Outcome::decoded) << what;
    }
    if (outcome == Outcome::unhandled) continue;
    const cv::Mat theirs = cv::imdecode(buffer, mode == Mode::grey ? cv::IMREAD_GRAYSCALE : cv::IMREAD_UNCHANGED);
    EXPECT_EQ(same(ours, theirs), "") << what << (mode == Mode::grey ? " (grey)" : " (unchanged)");
    EXPECT_EQ(outcome == Outcome::failed, ours.empty()) << what;
  }
}

// A PNG writer of this test's own (zlib and CRC-32 alone), for the kinds OpenCV does not write: grey+alpha,
// palettes, tRNS, 1/2/4-bit grey, a gAMA chunk.
void chunk(Bytes& out, const char* type, const Bytes& data) {
  const auto n = static_cast<std::uint32_t>(data.size());
  for (int s = 24; s >= 0; s -= 8) out.push_back(static_cast<std::uint8_t>(n >> s));
  const std::size_t start = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data.begin(), data.end());
  const auto crc = static_cast<std::uint32_t>(crc32(0, out.data() + start, static_cast<uInt>(out.size() - start)));
  for (int s = 24; s >= 0; s -= 8) out.push_back(static_cast<std::uint8_t>(crc >> s));
}

Bytes be32(std::uint32_t v) {
  return {static_cast<std::uint8_t>(v >> 24), static_cast<std::uint8_t>(v >> 16), static_cast<std::uint8_t>(v >> 8),
          static_cast<std::uint8_t>(v)};
}

struct PngKind {
  int colour_type;  // 0 grey, 2 RGB, 3 palette, 4 grey+alpha, 6 RGBA
  int depth;        // bits per sample
  bool trns;
  bool gamma;
};

Bytes make_png(const PngKind& k, int width, int height, std::mt19937& rng) {
  const int samples = k.colour_type == 2 ? 3 : k.colour_type == 4 ? 2 : k.colour_type == 6 ? 4 : 1;
  const int bits = samples * k.depth;
  const std::size_t row_bytes = (static_cast<std::size_t>(width) * static_cast<std::size_t>(bits) + 7) / 8;
  std::uniform_int_distribution<int> byte(0, 255);
  const int palette_size = 1 + byte(rng) % (1 << std::min(k.depth, 8));
  Bytes raw;
  for (int y = 0; y < height; ++y) {
    raw.push_back(0);  // filter: none
    for (std::size_t b = 0; b < row_bytes; ++b) {
      int v = byte(rng);
      if (k.colour_type == 3 && k.depth == 8) v %= palette_size;  // indices within the palette
      raw.push_back(static_cast<std::uint8_t>(v));
    }
  }
  Bytes out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  Bytes ihdr = be32(static_cast<std::uint32_t>(width));
  const Bytes h = be32(static_cast<std::uint32_t>(height));
  ihdr.insert(ihdr.end(), h.begin(), h.end());
  ihdr.insert(ihdr.end(), {static_cast<std::uint8_t>(k.depth), static_cast<std::uint8_t>(k.colour_type), 0, 0, 0});
  chunk(out, "IHDR", ihdr);
  if (k.gamma) chunk(out, "gAMA", be32(static_cast<std::uint32_t>(30000 + byte(rng) * 200)));
  if (k.colour_type == 3) {
    const int entries = k.depth == 8 ? palette_size : 1 << k.depth;
    Bytes plte;
    for (int i = 0; i < 3 * entries; ++i) plte.push_back(static_cast<std::uint8_t>(byte(rng)));
    chunk(out, "PLTE", plte);
    if (k.trns) {
      Bytes alpha;
      for (int i = 0; i < 1 + byte(rng) % entries; ++i) alpha.push_back(static_cast<std::uint8_t>(byte(rng)));
      chunk(out, "tRNS", alpha);
    }
  } else if (k.trns && (k.colour_type == 0 || k.colour_type == 2)) {
    Bytes key;
    const int max = (1 << k.depth) - 1;
    for (int i = 0; i < (k.colour_type == 0 ? 1 : 3); ++i) {
      const int v = (byte(rng) * 257) & max;
      key.push_back(static_cast<std::uint8_t>(v >> 8));
      key.push_back(static_cast<std::uint8_t>(v));
    }
    chunk(out, "tRNS", key);
  }
  uLongf size = compressBound(static_cast<uLong>(raw.size()));
  Bytes idat(size);
  EXPECT_EQ(compress2(idat.data(), &size, raw.data(), static_cast<uLong>(raw.size()), 6), Z_OK);
  idat.resize(size);
  chunk(out, "IDAT", idat);
  chunk(out, "IEND", {});
  return out;
}

cv::Size random_size(std::mt19937& rng, int i) {
  if (i == 0) return {1, 1};
  std::uniform_int_distribution<int> side(1, 37);
  return {side(rng) | 1, side(rng)};  // odd widths
}

cv::Mat random_image(std::mt19937& rng, cv::Size size, int type) {
  cv::Mat m(size, type);
  cv::randu(m, 0, CV_MAT_DEPTH(type) == CV_16U ? 65536 : 256);
  if (rng() % 2 == 0) cv::GaussianBlur(m, m, cv::Size(3, 3), 0);  // smooth, as photographs are, half the time
  return m;
}

Bytes opencv_encode(const std::string& ext, const cv::Mat& m, const std::vector<int>& params = {}) {
  Bytes out;
  EXPECT_TRUE(cv::imencode(ext, m, out, params));
  return out;
}

TEST(PngJpeg, PngKindsAsOpenCV) {
  std::mt19937 rng(7);
  const std::vector<PngKind> kinds = {
      {0, 1, false, false},  {0, 2, false, false}, {0, 4, true, false},  {0, 8, false, false}, {0, 8, true, true},
      {0, 16, false, false}, {0, 16, true, false}, {2, 8, false, false}, {2, 8, true, false},  {2, 8, false, true},
      {2, 16, false, false}, {2, 16, true, true},  {3, 1, false, false}, {3, 2, true, false},  {3, 4, false, false},
      {3, 8, false, false},  {3, 8, true, false},  {3, 8, true, true},   {4, 8, false, false}, {4, 8, false, true},
      {4, 16, false, false}, {6, 8, false, false}, {6, 8, false, true},  {6, 16, false, false}};
  for (const PngKind& k : kinds) {
    for (int i = 0; i < 6; ++i) {
      const cv::Size s = random_size(rng, i);
      expect_as_opencv(make_png(k, s.width, s.height, rng),
                       "PNG type " + std::to_string(k.colour_type) + " depth " + std::to_string(k.depth) +
                           (k.trns ? " tRNS" : "") + (k.gamma ? " gAMA" : "") + " " + std::to_string(s.width) + "x" +
                           std::to_string(s.height));
    }
  }
  for (const int type : {CV_8UC1, CV_8UC3, CV_8UC4, CV_16UC1, CV_16UC3, CV_16UC4}) {
    for (int i = 0; i < 6; ++i) {
      const cv::Mat m = random_image(rng, random_size(rng, i), type);
      expect_as_opencv(opencv_encode(".png", m), "OpenCV's PNG of type " + std::to_string(type));
      if (CV_MAT_DEPTH(type) == CV_8U && m.channels() != 4) {
        const Bytes ours = codecs::direct::encode_png(m);
        const cv::Mat back = cv::imdecode(ours, cv::IMREAD_UNCHANGED);
        EXPECT_EQ(same(back, m), "") << "our PNG read back by OpenCV";
        expect_as_opencv(ours, "our PNG");
      }
    }
  }
}

TEST(PngJpeg, JpegKindsAsOpenCV) {
  std::mt19937 rng(11);
  for (const int type : {CV_8UC1, CV_8UC3}) {
    for (int i = 0; i < 12; ++i) {
      const cv::Mat m = random_image(rng, random_size(rng, i), type);
      const int q = 1 + static_cast<int>(rng() % 100);
      const std::string what = std::to_string(m.cols) + "x" + std::to_string(m.rows) + " q" + std::to_string(q) +
                               (type == CV_8UC1 ? " grey" : " colour");
      expect_as_opencv(opencv_encode(".jpg", m, {cv::IMWRITE_JPEG_QUALITY, q}), "OpenCV's JPEG " + what);
      expect_as_opencv(opencv_encode(".jpg", m, {cv::IMWRITE_JPEG_QUALITY, q, cv::IMWRITE_JPEG_PROGRESSIVE, 1}),
                       "OpenCV's progressive JPEG " + what);
      expect_as_opencv(codecs::direct::encode_jpeg(m, q), "our JPEG " + what);
      expect_as_opencv(codecs::direct::encode_jpeg(m, q, true), "our progressive JPEG " + what);
      expect_as_opencv(opencv_encode(".jpg", m, {cv::IMWRITE_JPEG_QUALITY, q, cv::IMWRITE_JPEG_RST_INTERVAL, 2}),
                       "OpenCV's JPEG with restart markers " + what);
    }
  }
}

// Ours is deterministic and what OpenCV's own encoder writes for the same image, quality and defaults.
TEST(PngJpeg, EncodersAreDeterministic) {
  std::mt19937 rng(3);
  for (const int type : {CV_8UC1, CV_8UC3}) {
    const cv::Mat m = random_image(rng, cv::Size(33, 17), type);
    EXPECT_EQ(codecs::direct::encode_png(m), codecs::direct::encode_png(m));
    EXPECT_EQ(codecs::direct::encode_jpeg(m, 90), codecs::direct::encode_jpeg(m, 90));
    const cv::Mat back = cv::imdecode(codecs::encode_jpeg(m, 90), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(back.type(), m.type());
    EXPECT_LT(cv::norm(back, m, cv::NORM_L1) / static_cast<double>(m.total() * m.channels()), 40.0);
  }
  EXPECT_THROW(codecs::encode_png(cv::Mat(2, 2, CV_16UC1)), std::runtime_error);
  EXPECT_THROW(codecs::encode_jpeg(cv::Mat(2, 2, CV_8UC4), 90), std::runtime_error);
  EXPECT_THROW(codecs::encode_png(cv::Mat()), std::runtime_error);
}

// Cut or damaged bytes: ours fails where OpenCV fails and decodes what OpenCV decodes, never crashing.
TEST(PngJpeg, CorruptBytesAsOpenCV) {
  std::mt19937 rng(5);
  const cv::Mat colour = random_image(rng, cv::Size(29, 23), CV_8UC3);
  const std::vector<Bytes> images = {opencv_encode(".png", colour), make_png({3, 8, true, false}, 19, 7, rng),
                                     opencv_encode(".jpg", colour, {cv::IMWRITE_JPEG_QUALITY, 80}),
                                     opencv_encode(".jpg", colour, {cv::IMWRITE_JPEG_PROGRESSIVE, 1}),
                                     codecs::direct::encode_jpeg(colour, 60)};
  for (std::size_t k = 0; k < images.size(); ++k) {
    const Bytes& image = images[k];
    for (std::size_t cut = 1; cut < image.size(); cut += 1 + cut / 8) {
      expect_as_opencv(Bytes(image.begin(), image.begin() + static_cast<std::ptrdiff_t>(cut)),
                       "image " + std::to_string(k) + " cut at " + std::to_string(cut), false);
    }
    for (int t = 0; t < 150; ++t) {
      Bytes damaged = image;
      for (int f = 0; f < 1 + t % 4; ++f) {
        damaged[8 + rng() % (damaged.size() - 8)] = static_cast<std::uint8_t>(rng());
      }
      expect_as_opencv(damaged, "image " + std::to_string(k) + " damaged, trial " + std::to_string(t), false);
      (void)codecs::decode(damaged);  // through the plugin when ours leaves it: no crash either way
    }
  }
  cv::Mat out;
  EXPECT_EQ(codecs::direct::decode(Bytes{0x89, 'P', 'N', 'G'}, Mode::unchanged, out), Outcome::unhandled);
  EXPECT_EQ(codecs::direct::decode(Bytes{0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'}, Mode::unchanged, out),
            Outcome::failed);
  EXPECT_TRUE(codecs::decode(Bytes{0xff, 0xd8, 0xff, 0xe0, 0, 0}).empty());
}

// Other formats go through the plugin, decoded as OpenCV decodes them.
TEST(PngJpeg, OtherFormatsThroughThePlugin) {
  std::mt19937 rng(9);
  const cv::Mat m = random_image(rng, cv::Size(13, 9), CV_8UC3);
  for (const std::string ext : {".bmp", ".tiff", ".ppm"}) {
    const Bytes bytes = opencv_encode(ext, m);
    cv::Mat out;
    EXPECT_EQ(codecs::direct::decode(bytes, Mode::unchanged, out), Outcome::unhandled);
    EXPECT_EQ(same(codecs::decode(bytes), cv::imdecode(bytes, cv::IMREAD_UNCHANGED)), "") << ext;
  }
}

Bytes read_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// read_grey (a file) as imread(IMREAD_GRAYSCALE), including a JPEG with an Exif orientation, which OpenCV
// applies to grey reads (left to the plugin).
TEST(PngJpeg, ReadGreyAsImread) {
  seqtopo::test_support::TempDir dir;
  std::mt19937 rng(13);
  const cv::Mat m = random_image(rng, cv::Size(21, 11), CV_8UC3);
  std::vector<std::pair<std::string, Bytes>> files = {{"a.png", opencv_encode(".png", m)},
                                                      {"b.jpg", opencv_encode(".jpg", m)},
                                                      {"c.png", make_png({2, 16, true, true}, 9, 5, rng)},
                                                      {"d.bmp", opencv_encode(".bmp", m)}};
  // An APP1 Exif segment (big-endian TIFF, one IFD entry: orientation 6, turned 90 degrees) after SOI.
  Bytes exif = {0xff, 0xe1, 0,    0,    'E', 'x', 'i', 'f', 0, 0, 'M', 'M', 0, 42, 0, 0, 0, 8,
                0,    1,    0x01, 0x12, 0,   3,   0,   0,   0, 1, 0,   6,   0, 0,  0, 0, 0, 0};
  exif[3] = static_cast<std::uint8_t>(exif.size() - 2);
  Bytes turned = opencv_encode(".jpg", m);
  turned.insert(turned.begin() + 2, exif.begin(), exif.end());
  files.emplace_back("e.jpg", turned);
  for (const auto& [name, bytes] : files) {
    const fs::path file = dir.path / name;
    std::ofstream(file, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    EXPECT_EQ(same(codecs::read_grey(file), cv::imread(file.string(), cv::IMREAD_GRAYSCALE)), "") << name;
  }
  EXPECT_EQ(cv::imread((dir.path / "e.jpg").string(), cv::IMREAD_GRAYSCALE).size(), cv::Size(11, 21));
  EXPECT_TRUE(codecs::read_grey(dir.path / "missing.png").empty());
}

std::vector<fs::path> images_in(const fs::path& folder, std::size_t every) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const std::string ext = entry.path().extension().string();
    if (ext == ".png" || ext == ".jpg") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  std::vector<fs::path> kept;
  for (std::size_t i = 0; i < files.size(); i += every) kept.push_back(files[i]);
  return kept;
}

TEST(PngJpeg, BundledAndSharedDataAsOpenCV) {
  std::size_t checked = 0;
  for (const auto& [folder, every] : std::vector<std::pair<fs::path, std::size_t>>{
           {fs::path(SEQTOPO_SOURCE_DIR) / "data/rtabmap-corridor", 1},
           {fs::path(SEQTOPO_SHARED_DATA_DIR) / "nordland-64x32/summer", 97},
           {fs::path(SEQTOPO_SHARED_DATA_DIR) / "nordland-64x32/winter", 89}}) {
    for (const fs::path& file : images_in(folder, every)) {
      expect_as_opencv(read_bytes(file), file.string());
      EXPECT_EQ(same(codecs::read_grey(file), cv::imread(file.string(), cv::IMREAD_GRAYSCALE)), "") << file;
      ++checked;
    }
  }
  EXPECT_GT(checked, 0U);
}

}  // namespace
}  // namespace seqtopo::image
