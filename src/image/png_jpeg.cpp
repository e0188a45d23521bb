#include "png_jpeg.hpp"

// clang-format off
#include <png.h>
#include <zlib.h>
#include <cstdio>  // jpeglib.h uses FILE and size_t without including their headers
#include <jpeglib.h>
#include <jerror.h>
// clang-format on

#include <csetjmp>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>

// libpng and libjpeg report errors by longjmp. Each setjmp is in a function of its own that holds no object
// with a destructor (only C structures and pointers), so a longjmp out of the library never skips one; the
// Mats and vectors live in the callers, which the longjmp does not cross.
namespace seqtopo::image::codecs::direct {

namespace {

// OpenCV's limits on an image to decode (its CV_IO_MAX_IMAGE_* defaults). Beyond them, or when they are
// changed through OpenCV's environment variables, the plugin decides.
bool within_opencv_limits(std::uint64_t width, std::uint64_t height) {
  for (const char* name : {"OPENCV_IO_MAX_IMAGE_WIDTH", "OPENCV_IO_MAX_IMAGE_HEIGHT", "OPENCV_IO_MAX_IMAGE_PIXELS"}) {
    if (std::getenv(name) != nullptr) return false;
  }
  return width > 0 && height > 0 && width <= (1U << 20) && height <= (1U << 20) && width * height <= (1ULL << 30);
}

bool is_png(std::span<const std::uint8_t> b) {
  static constexpr std::uint8_t kSignature[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  return b.size() >= sizeof kSignature && std::memcmp(b.data(), kSignature, sizeof kSignature) == 0;
}

bool is_jpeg(std::span<const std::uint8_t> b) {  // OpenCV's JPEG signature
  return b.size() >= 3 && b[0] == 0xff && b[1] == 0xd8 && b[2] == 0xff;
}

// ---- PNG ----

struct PngInput {
  const std::uint8_t* data;
  std::size_t size;
  std::size_t offset;
};

void png_read_bytes(png_structp png, png_bytep out, png_size_t count) {
  auto* in = static_cast<PngInput*>(png_get_io_ptr(png));
  if (count > in->size - in->offset) png_error(png, "truncated");
  std::memcpy(out, in->data + in->offset, count);
  in->offset += count;
}

[[noreturn]] void png_fail(png_structp png, png_const_charp) { png_longjmp(png, 1); }
void png_ignore(png_structp, png_const_charp) {}  // warnings (a damaged ancillary chunk) stay off stderr

struct PngLayout {
  png_uint_32 width, height;
  int channels;
  bool sixteen;
  png_size_t row_bytes;
};

// The transforms of OpenCV 4.6's PngDecoder::readData for the type its readHeader announces: tRNS makes
// RGB and palette images BGRA, grey+alpha is BGRA, grey keeps one channel (its tRNS dropped); 16-bit samples
// stay 16-bit unless grey is asked for; grey from colour by libpng's own rgb_to_gray.
bool png_prepare(png_structp png, png_infop info, Mode mode, PngLayout* layout) {
  if (setjmp(png_jmpbuf(png)) != 0) return false;
  png_read_info(png, info);
  png_uint_32 width = 0;
  png_uint_32 height = 0;
  int depth = 0;
  int type = 0;
  png_get_IHDR(png, info, &width, &height, &depth, &type, nullptr, nullptr, nullptr);
  int channels = 1;
  if (type == PNG_COLOR_TYPE_RGB || type == PNG_COLOR_TYPE_PALETTE) {
    png_bytep alpha = nullptr;
    int transparent = 0;
    png_color_16p colour = nullptr;
    png_get_tRNS(png, info, &alpha, &transparent, &colour);
    channels = transparent > 0 ? 4 : 3;
  } else if (type == PNG_COLOR_TYPE_GRAY_ALPHA || type == PNG_COLOR_TYPE_RGB_ALPHA) {
    channels = 4;
  }
  bool sixteen = depth == 16;
  if (mode == Mode::grey) {
    channels = 1;
    sixteen = false;
  }
  if (depth == 16 && !sixteen) {
    png_set_strip_16(png);
  } else {
    png_set_swap(png);  // 16-bit samples in the host's (little-endian) order
  }
  if (channels < 4) {
    png_set_strip_alpha(png);
  } else {
    png_set_tRNS_to_alpha(png);
  }
  if (type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if ((type & PNG_COLOR_MASK_COLOR) == 0 && depth < 8) png_set_expand_gray_1_2_4_to_8(png);
  if ((type & PNG_COLOR_MASK_COLOR) != 0 && channels > 1) {
    png_set_bgr(png);
  } else if (channels > 1) {
    png_set_gray_to_rgb(png);
  } else {
    png_set_rgb_to_gray(png, 1, 0.299, 0.587);
  }
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  *layout = PngLayout{width, height, channels, sixteen, png_get_rowbytes(png, info)};
  return true;
}

bool png_read_rows(png_structp png, png_infop end, png_bytepp rows) {
  if (setjmp(png_jmpbuf(png)) != 0) return false;
  png_read_image(png, rows);
  png_read_end(png, end);
  return true;
}

struct PngReader {
  png_structp png = nullptr;
  png_infop info = nullptr;
  png_infop end = nullptr;
  PngReader() {
    png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, png_fail, png_ignore);
    if (png != nullptr) {
      info = png_create_info_struct(png);
      end = png_create_info_struct(png);
    }
  }
  ~PngReader() { png_destroy_read_struct(&png, &info, &end); }
  PngReader(const PngReader&) = delete;
  PngReader& operator=(const PngReader&) = delete;
};

Outcome decode_png(std::span<const std::uint8_t> bytes, Mode mode, cv::Mat& out) {
  PngInput input{bytes.data(), bytes.size(), 0};
  PngReader reader;
  if (reader.png == nullptr || reader.info == nullptr || reader.end == nullptr) return Outcome::unhandled;
  png_set_read_fn(reader.png, &input, png_read_bytes);
  PngLayout layout{};
  if (!png_prepare(reader.png, reader.info, mode, &layout)) return Outcome::failed;
  if (!within_opencv_limits(layout.width, layout.height)) return Outcome::unhandled;
  cv::Mat image(static_cast<int>(layout.height), static_cast<int>(layout.width),
                CV_MAKETYPE(layout.sixteen ? CV_16U : CV_8U, layout.channels));
  if (layout.row_bytes != image.cols * image.elemSize()) return Outcome::unhandled;  // not a layout foreseen
  std::vector<png_bytep> rows(static_cast<std::size_t>(image.rows));
  for (int r = 0; r < image.rows; ++r) rows[static_cast<std::size_t>(r)] = image.ptr(r);
  if (!png_read_rows(reader.png, reader.end, rows.data())) return Outcome::failed;
#ifdef PNG_eXIf_SUPPORTED
  // OpenCV turns a grey read by the image's Exif orientation.
  if (mode == Mode::grey && (png_get_valid(reader.png, reader.info, PNG_INFO_eXIf) != 0 ||
                             png_get_valid(reader.png, reader.end, PNG_INFO_eXIf) != 0)) {
    return Outcome::unhandled;
  }
#endif
  out = image;
  return Outcome::decoded;
}

// ---- JPEG ----

struct JpegFailure {
  jpeg_error_mgr manager;
  std::jmp_buf jump;
};

[[noreturn]] void jpeg_fail(j_common_ptr common) { std::longjmp(reinterpret_cast<JpegFailure*>(common->err)->jump, 1); }
void jpeg_quiet(j_common_ptr) {}  // warnings ("Corrupt JPEG data: ...") stay off stderr

void jpeg_error_handling(jpeg_error_mgr* manager) {
  jpeg_std_error(manager);
  manager->error_exit = jpeg_fail;
  manager->output_message = jpeg_quiet;
}

// OpenCV reads a buffer through a source that suspends when the bytes run out (it never supplies more), not
// one that makes up an end of image: a truncated JPEG then fails rather than decoding grey.
void source_nothing(j_decompress_ptr) {}
boolean source_no_more(j_decompress_ptr) { return FALSE; }
void source_skip(j_decompress_ptr info, long count) {
  jpeg_source_mgr* source = info->src;
  if (count <= 0) return;
  const auto n = static_cast<std::size_t>(count);
  if (n > source->bytes_in_buffer) {
    source->next_input_byte += source->bytes_in_buffer;
    source->bytes_in_buffer = 0;
  } else {
    source->next_input_byte += n;
    source->bytes_in_buffer -= n;
  }
}

enum class Step { done, suspended, error };

struct JpegDecoder {  // C structures only (see the top of the file)
  jpeg_decompress_struct info;
  JpegFailure failure;
  jpeg_source_mgr source;
  bool created;
};

Step jpeg_open(JpegDecoder* d, const std::uint8_t* data, std::size_t size) {
  d->info.err = &d->failure.manager;
  jpeg_error_handling(&d->failure.manager);
  if (setjmp(d->failure.jump) != 0) return Step::error;
  jpeg_create_decompress(&d->info);
  d->created = true;
  d->source.next_input_byte = data;
  d->source.bytes_in_buffer = size;
  d->source.init_source = source_nothing;
  d->source.fill_input_buffer = source_no_more;
  d->source.skip_input_data = source_skip;
  d->source.resync_to_restart = jpeg_resync_to_restart;
  d->source.term_source = source_nothing;
  d->info.src = &d->source;
  jpeg_save_markers(&d->info, JPEG_APP0 + 1, 0xffff);  // to see the Exif (APP1) OpenCV applies to grey reads
  if (jpeg_read_header(&d->info, TRUE) != JPEG_HEADER_OK) return Step::suspended;
  jpeg_calc_output_dimensions(&d->info);
  return Step::done;
}

// As OpenCV 4.6's JpegDecoder::readData: libjpeg-turbo's own BGR, or its own grey (Y alone from YCbCr).
Step jpeg_start(JpegDecoder* d, bool grey) {
  if (setjmp(d->failure.jump) != 0) return Step::error;
  d->info.out_color_space = grey ? JCS_GRAYSCALE : JCS_EXT_BGR;
  d->info.out_color_components = grey ? 1 : 3;
  return jpeg_start_decompress(&d->info) ? Step::done : Step::suspended;
}

Step jpeg_rows(JpegDecoder* d, std::uint8_t* data, std::size_t step, JDIMENSION height) {
  if (setjmp(d->failure.jump) != 0) return Step::error;
  for (JDIMENSION y = 0; y < height; ++y) {
    JSAMPROW row = data + static_cast<std::size_t>(y) * step;
    if (jpeg_read_scanlines(&d->info, &row, 1) != 1) return Step::suspended;
  }
  return Step::done;
}

Step jpeg_finish(JpegDecoder* d) {
  if (setjmp(d->failure.jump) != 0) return Step::error;
  return jpeg_finish_decompress(&d->info) ? Step::done : Step::suspended;
}

bool has_app1(const jpeg_decompress_struct& info) {
  for (jpeg_saved_marker_ptr m = info.marker_list; m != nullptr; m = m->next) {
    if (m->marker == JPEG_APP0 + 1) return true;
  }
  return false;
}

Outcome decode_jpeg(std::span<const std::uint8_t> bytes, Mode mode, cv::Mat& out) {
  JpegDecoder d{};
  struct Close {
    JpegDecoder& d;
    ~Close() {
      if (d.created) jpeg_destroy_decompress(&d.info);
    }
  } close{d};
  // A grey read is OpenCV's imread, whose file source makes up an end of image where the buffer's suspends:
  // any trouble there is the plugin's to judge.
  const bool grey = mode == Mode::grey;
  const auto trouble = [grey](Step s) { return grey || s == Step::suspended ? Outcome::unhandled : Outcome::failed; };
  if (const Step s = jpeg_open(&d, bytes.data(), bytes.size()); s != Step::done) return trouble(s);
  const int components = d.info.num_components;
  if (components != 1 && components != 3) return Outcome::unhandled;  // CMYK and the like
  if (grey && has_app1(d.info)) return Outcome::unhandled;            // OpenCV applies the Exif orientation
  if (!within_opencv_limits(d.info.output_width, d.info.output_height)) return Outcome::unhandled;
  cv::Mat image(static_cast<int>(d.info.output_height), static_cast<int>(d.info.output_width),
                grey || components == 1 ? CV_8UC1 : CV_8UC3);
  if (const Step s = jpeg_start(&d, image.channels() == 1); s != Step::done) return trouble(s);
  if (d.info.output_components != image.channels() || static_cast<int>(d.info.output_width) != image.cols ||
      static_cast<int>(d.info.output_height) != image.rows) {
    return Outcome::unhandled;
  }
  if (const Step s = jpeg_rows(&d, image.data, image.step, d.info.output_height); s != Step::done) return trouble(s);
  if (jpeg_finish(&d) == Step::error) return Outcome::unhandled;  // after the last row: OpenCV's result unclear
  out = image;
  return Outcome::decoded;
}

// ---- encoding ----

void png_write_bytes(png_structp png, png_bytep data, png_size_t count) {
  auto* out = static_cast<std::vector<std::uint8_t>*>(png_get_io_ptr(png));
  bool stored = true;
  try {
    out->insert(out->end(), data, data + count);
  } catch (...) {
    stored = false;
  }
  if (!stored) png_error(png, "out of memory");  // outside the handler: no longjmp out of a catch
}
void png_flush_nothing(png_structp) {}

// OpenCV's PNG defaults: the SUB filter, zlib's fastest level and its run-length strategy.
bool png_write_all(png_structp png, png_infop info, png_uint_32 width, png_uint_32 height, int type, png_bytepp rows) {
  if (setjmp(png_jmpbuf(png)) != 0) return false;
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
  png_set_compression_level(png, Z_BEST_SPEED);
  png_set_compression_strategy(png, Z_RLE);
  png_set_IHDR(png, info, width, height, 8, type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  png_set_bgr(png);
  png_write_image(png, rows);
  png_write_end(png, info);
  return true;
}

void require_8bit_grey_or_bgr(const cv::Mat& image, const char* format) {
  if (image.empty() || image.depth() != CV_8U || (image.channels() != 1 && image.channels() != 3)) {
    throw std::runtime_error(std::string("image codecs: cannot encode ") + format +
                             " (an 8-bit grey or BGR image is expected)");
  }
}

struct JpegSink {
  jpeg_destination_mgr manager;
  unsigned char* data;
  std::size_t capacity;
};

void sink_start(j_compress_ptr info) {
  auto* sink = reinterpret_cast<JpegSink*>(info->dest);
  sink->manager.next_output_byte = sink->data;
  sink->manager.free_in_buffer = sink->capacity;
}

boolean sink_grow(j_compress_ptr info) {  // the buffer is full
  auto* sink = reinterpret_cast<JpegSink*>(info->dest);
  auto* bigger = static_cast<unsigned char*>(std::realloc(sink->data, 2 * sink->capacity));
  if (bigger == nullptr) ERREXIT(info, JERR_OUT_OF_MEMORY);
  sink->data = bigger;
  sink->manager.next_output_byte = bigger + sink->capacity;
  sink->manager.free_in_buffer = sink->capacity;
  sink->capacity *= 2;
  return TRUE;
}

void sink_end(j_compress_ptr) {}

struct JpegEncoder {  // C structures only
  jpeg_compress_struct info;
  JpegFailure failure;
  JpegSink sink;
  bool created;
};

// OpenCV's JPEG defaults: libjpeg's, with the quality's baseline tables.
bool jpeg_encode(JpegEncoder* e, const std::uint8_t* data, std::size_t step, int width, int height, int channels,
                 int quality, bool progressive) {
  e->info.err = &e->failure.manager;
  jpeg_error_handling(&e->failure.manager);
  if (setjmp(e->failure.jump) != 0) return false;
  jpeg_create_compress(&e->info);
  e->created = true;
  e->sink.manager.init_destination = sink_start;
  e->sink.manager.empty_output_buffer = sink_grow;
  e->sink.manager.term_destination = sink_end;
  e->info.dest = &e->sink.manager;
  e->info.image_width = static_cast<JDIMENSION>(width);
  e->info.image_height = static_cast<JDIMENSION>(height);
  e->info.input_components = channels;
  e->info.in_color_space = channels == 1 ? JCS_GRAYSCALE : JCS_EXT_BGR;
  jpeg_set_defaults(&e->info);
  jpeg_set_quality(&e->info, quality, TRUE);
  if (progressive) jpeg_simple_progression(&e->info);
  jpeg_start_compress(&e->info, TRUE);
  for (int y = 0; y < height; ++y) {
    auto row = const_cast<JSAMPROW>(data + static_cast<std::size_t>(y) * step);
    jpeg_write_scanlines(&e->info, &row, 1);
  }
  jpeg_finish_compress(&e->info);
  return true;
}

}  // namespace

Outcome decode(std::span<const std::uint8_t> bytes, Mode mode, cv::Mat& out) {
  out.release();
  if (is_png(bytes)) return decode_png(bytes, mode, out);
  if (is_jpeg(bytes)) return decode_jpeg(bytes, mode, out);
  return Outcome::unhandled;
}

std::vector<std::uint8_t> encode_png(const cv::Mat& image) {
  require_8bit_grey_or_bgr(image, ".png");
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, png_fail, png_ignore);
  png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
  struct Close {
    png_structp& png;
    png_infop& info;
    ~Close() { png_destroy_write_struct(&png, &info); }
  } close{png, info};
  if (info == nullptr) throw std::runtime_error("image codecs: cannot encode .png (out of memory)");
  std::vector<std::uint8_t> out;
  png_set_write_fn(png, &out, png_write_bytes, png_flush_nothing);
  std::vector<png_bytep> rows(static_cast<std::size_t>(image.rows));
  for (int r = 0; r < image.rows; ++r) rows[static_cast<std::size_t>(r)] = const_cast<png_bytep>(image.ptr(r));
  if (!png_write_all(png, info, static_cast<png_uint_32>(image.cols), static_cast<png_uint_32>(image.rows),
                     image.channels() == 1 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGB, rows.data())) {
    throw std::runtime_error("image codecs: cannot encode .png");
  }
  return out;
}

std::vector<std::uint8_t> encode_jpeg(const cv::Mat& image, int quality, bool progressive) {
  require_8bit_grey_or_bgr(image, ".jpg");
  JpegEncoder e{};
  e.sink.capacity = 1 << 16;
  e.sink.data = static_cast<unsigned char*>(std::malloc(e.sink.capacity));
  struct Close {
    JpegEncoder& e;
    ~Close() {
      if (e.created) jpeg_destroy_compress(&e.info);
      std::free(e.sink.data);
    }
  } close{e};
  if (e.sink.data == nullptr ||
      !jpeg_encode(&e, image.data, image.step, image.cols, image.rows, image.channels(), quality, progressive)) {
    throw std::runtime_error("image codecs: cannot encode .jpg");
  }
  return {e.sink.data, e.sink.data + (e.sink.capacity - e.sink.manager.free_in_buffer)};
}

}  // namespace seqtopo::image::codecs::direct
