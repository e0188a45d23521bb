#include "seqtopo/io/npy.hpp"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <string_view>
#include <type_traits>
#include <vector>

#include "seqtopo/core/input_error.hpp"
#include "seqtopo/core/text_file.hpp"
#include "seqtopo/io/atomic_output.hpp"

static_assert(std::endian::native == std::endian::little, "the .npy reader assumes a little-endian machine");

namespace seqtopo::io {
namespace {

constexpr char kMagic[] = "\x93NUMPY";

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& message) {
  throw InputError(path.string(), message);
}

// A value of the header's Python literal: a quoted string, a bare word (True, 12, -1), or a tuple / list / dict
// of values (dicts keep their keys in `keys`).
struct Literal {
  enum Kind { string, word, tuple, list, dict } kind = word;
  std::string text;  // the string's contents, the word, or the source text of a tuple / list / dict
  std::vector<Literal> items;
  std::vector<std::string> keys;
};

// The header dict parsed as Python's ast.literal_eval reads it (numpy's own reader): keys are those of the top
// level only, so a 'shape' inside another key's string or a nested dict is not the shape.
class HeaderParser {
 public:
  HeaderParser(const std::string& text, const std::filesystem::path& path) : t_(text), path_(path) {}

  Literal parse() {
    Literal v = value();
    skip_space();
    if (at_ != t_.size()) bad("text after the dict");
    if (v.kind != Literal::dict) bad("not a dict");
    return v;
  }

 private:
  [[noreturn]] void bad(const std::string& why) const {
    fail(path_, "not a valid .npy header (" + why + " at byte " + std::to_string(at_) + ")");
  }
  void skip_space() {
    while (at_ < t_.size() && std::isspace(static_cast<unsigned char>(t_[at_]))) ++at_;
  }
  Literal value() {
    if (++depth_ > 32) bad("nested too deep");
    skip_space();
    if (at_ >= t_.size()) bad("a value is missing");
    Literal v;
    const std::size_t start = at_;
    const char c = t_[at_];
    if (c == '\'' || c == '"') {
      v.kind = Literal::string;
      for (++at_;; ++at_) {
        if (at_ >= t_.size() || t_[at_] == '\n') bad("a string is not closed");
        if (t_[at_] == '\\') {
          if (++at_ >= t_.size()) bad("a string is not closed");
          v.text += t_[at_];
        } else if (t_[at_] == c) {
          ++at_;
          break;
        } else {
          v.text += t_[at_];
        }
      }
    } else if (c == '(' || c == '[' || c == '{') {
      const char close = c == '(' ? ')' : c == '[' ? ']' : '}';
      v.kind = c == '(' ? Literal::tuple : c == '[' ? Literal::list : Literal::dict;
      ++at_;
      bool comma = false;  // "(12)" is the number 12, "(12,)" a tuple
      for (;;) {
        skip_space();
        if (at_ < t_.size() && t_[at_] == close) {
          ++at_;
          break;
        }
        if (v.kind == Literal::dict) {
          const Literal key = value();
          if (key.kind != Literal::string) bad("a key is not a string");
          skip_space();
          if (at_ >= t_.size() || t_[at_] != ':') bad("':' expected after '" + key.text + "'");
          ++at_;
          v.keys.push_back(key.text);
        }
        v.items.push_back(value());
        skip_space();
        if (at_ < t_.size() && t_[at_] == ',') {
          ++at_;
          comma = true;
        } else if (at_ >= t_.size() || t_[at_] != close) {
          bad(std::string("',' or '") + close + "' expected");
        }
      }
      if (v.kind == Literal::tuple && v.items.size() == 1 && !comma) {
        Literal inner = std::move(v.items.front());
        --depth_;
        return inner;
      }
      v.text = t_.substr(start, at_ - start);
    } else {
      while (at_ < t_.size() && (std::isalnum(static_cast<unsigned char>(t_[at_])) || t_[at_] == '_' ||
                                 t_[at_] == '-' || t_[at_] == '+' || t_[at_] == '.')) {
        ++at_;
      }
      if (at_ == start) bad(std::string("unexpected '") + c + "'");
      v.text = t_.substr(start, at_ - start);
    }
    --depth_;
    return v;
  }

  const std::string& t_;
  const std::filesystem::path& path_;
  std::size_t at_ = 0;
  int depth_ = 0;
};

// The value of `key` in the header dict: numpy's keys are exactly descr, fortran_order and shape.
const Literal& dict_value(const Literal& dict, const std::string& key, const std::filesystem::path& path) {
  const Literal* found = nullptr;
  for (std::size_t k = 0; k < dict.keys.size(); ++k) {
    if (dict.keys[k] != key) continue;
    if (found) fail(path, "not a valid .npy header ('" + key + "' twice)");
    found = &dict.items[k];
  }
  if (!found) fail(path, "not a valid .npy header (no '" + key + "')");
  return *found;
}

}  // namespace

NpyHeader read_npy_header(const std::filesystem::path& path) {
  require_regular_file(path, ".npy file");  // /dev/zero or a FIFO would be read forever
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open file");
  char magic[6];
  std::uint8_t version[2];
  if (!in.read(magic, 6) || std::memcmp(magic, kMagic, 6) != 0) fail(path, "not a .npy file (bad magic)");
  if (!in.read(reinterpret_cast<char*>(version), 2)) fail(path, "truncated .npy header");
  std::size_t header_len = 0;
  std::size_t prefix = 0;
  if (version[0] == 1) {
    std::uint16_t len = 0;
    if (!in.read(reinterpret_cast<char*>(&len), 2)) fail(path, "truncated .npy header");
    header_len = len;
    prefix = 10;
  } else if (version[0] == 2 || version[0] == 3) {
    std::uint32_t len = 0;
    if (!in.read(reinterpret_cast<char*>(&len), 4)) fail(path, "truncated .npy header");
    header_len = len;
    prefix = 12;
  } else {
    fail(path, "unsupported .npy version " + std::to_string(version[0]));
  }
  if (header_len > (1U << 20)) fail(path, "implausible .npy header length");
  std::string header(header_len, '\0');
  if (!in.read(header.data(), static_cast<std::streamsize>(header_len))) fail(path, "truncated .npy header");

  NpyHeader h;
  h.data_offset = prefix + header_len;
  const Literal dict = HeaderParser(header, path).parse();
  for (const std::string& key : dict.keys) {
    if (key != "descr" && key != "fortran_order" && key != "shape") {
      fail(path, "not a valid .npy header (unknown key '" + key + "'; numpy writes descr, fortran_order and shape)");
    }
  }
  const Literal& descr_value = dict_value(dict, "descr", path);
  const std::string descr = descr_value.text;
  // descr: byte order ('<' little, '>' big, '=' native, '|' not applicable), kind, bytes per value.
  const auto unsupported = [&] {
    fail(path, "unsupported dtype '" + descr +
                   "' (need floats of 2, 4 or 8 bytes, integers of 1 to 8 bytes or booleans, as numpy saves them)");
  };
  if (descr_value.kind != Literal::string || descr.size() < 3 ||
      std::string_view("<>=|").find(descr[0]) == std::string_view::npos) {
    unsupported();
  }
  h.dtype = descr;
  h.big_endian = descr[0] == '>';
  h.kind = descr[1];
  const std::string width = descr.substr(2);
  h.item = width == "1" ? 1 : width == "2" ? 2 : width == "4" ? 4 : width == "8" ? 8 : 0;
  const bool known = (h.kind == 'f' && h.item >= 2) || ((h.kind == 'i' || h.kind == 'u') && h.item >= 1) ||
                     (h.kind == 'b' && h.item == 1);
  if (!known) unsupported();
  const Literal& fortran = dict_value(dict, "fortran_order", path);
  if (fortran.kind == Literal::word && fortran.text == "True") {
    h.fortran_order = true;
  } else if (fortran.kind != Literal::word || fortran.text != "False") {
    fail(path, "not a valid .npy header (fortran_order is " + fortran.text + ", not True or False)");
  }
  const Literal& shape_value = dict_value(dict, "shape", path);
  const std::string shape = shape_value.text;
  if (shape_value.kind != Literal::tuple) fail(path, "not a valid .npy header (shape " + shape + " is not a tuple)");
  for (const Literal& d : shape_value.items) {
    const std::string& v = d.text;
    const std::size_t sign = !v.empty() && (v[0] == '-' || v[0] == '+') ? 1 : 0;
    const bool integer = d.kind == Literal::word && v.size() > sign &&
                         std::all_of(v.begin() + static_cast<std::ptrdiff_t>(sign), v.end(),
                                     [](char c) { return c >= '0' && c <= '9'; });
    if (!integer) fail(path, "not a valid .npy header (shape " + shape + " holds " + v + ", not an integer)");
    if (v[0] == '-' && v.find_first_not_of('0', 1) != std::string::npos) {
      fail(path, "shape " + shape + " has a negative dimension (numpy: negative dimensions are not allowed)");
    }
    std::size_t value = 0;
    for (std::size_t k = sign; k < v.size(); ++k) {
      const auto digit = static_cast<std::size_t>(v[k] - '0');
      if (value > (std::numeric_limits<std::size_t>::max() - digit) / 10) fail(path, "implausible shape " + shape);
      value = value * 10 + digit;
    }
    h.shape.push_back(value);
  }
  // The data must be in the file: every size is checked against the file's, without a product that wraps
  // (a shape of 2^61 rows of 8 bytes would otherwise pass and fail later as "out of memory").
  const std::size_t item = h.item;
  in.seekg(0, std::ios::end);
  const auto end = in.tellg();
  if (end < 0) fail(path, "cannot read file size");
  const auto file_size = static_cast<std::size_t>(end);
  const std::size_t room = file_size >= h.data_offset ? (file_size - h.data_offset) / item : 0;
  std::size_t count = 1;
  for (const std::size_t extent : h.shape) {
    if (extent == 0) {
      count = 0;
      break;
    }
    if (count > room / extent) {
      fail(path, "truncated data: shape " + shape + " needs more than the " +
                     std::to_string(file_size - std::min(file_size, h.data_offset)) + " data bytes in the file");
    }
    count *= extent;
  }
  return h;
}

namespace {

// IEEE 754 half precision to float (numpy's float16): subnormals, infinities and NaN included.
float half_to_float(std::uint16_t h) {
  const std::uint32_t sign = static_cast<std::uint32_t>(h & 0x8000U) << 16;
  const std::uint32_t exponent = (h >> 10) & 0x1FU, mantissa = h & 0x3FFU;
  if (exponent == 0) {
    const float magnitude = std::ldexp(static_cast<float>(mantissa), -24);
    return sign ? -magnitude : magnitude;
  }
  const std::uint32_t bits =
      exponent == 0x1F ? sign | 0x7F800000U | (mantissa << 13) : sign | ((exponent + 112) << 23) | (mantissa << 13);
  return std::bit_cast<float>(bits);
}

template <typename V>
V load(const unsigned char* p) {
  V v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// The value at `raw`, in the header's type and byte order.
double value_at(const NpyHeader& h, const unsigned char* raw) {
  unsigned char swapped[8];
  if (h.big_endian && h.item > 1) {
    std::reverse_copy(raw, raw + h.item, swapped);
    raw = swapped;
  }
  switch (h.kind) {
    case 'f':
      return h.item == 4 ? load<float>(raw) : h.item == 8 ? load<double>(raw) : half_to_float(load<std::uint16_t>(raw));
    case 'i':
      return h.item == 1   ? load<std::int8_t>(raw)
             : h.item == 2 ? load<std::int16_t>(raw)
             : h.item == 4 ? load<std::int32_t>(raw)
                           : static_cast<double>(load<std::int64_t>(raw));
    case 'u':
      return h.item == 1   ? load<std::uint8_t>(raw)
             : h.item == 2 ? load<std::uint16_t>(raw)
             : h.item == 4 ? load<std::uint32_t>(raw)
                           : static_cast<double>(load<std::uint64_t>(raw));
    default:  // 'b'
      return raw[0] != 0 ? 1.0 : 0.0;
  }
}

}  // namespace

template <typename T>
DenseMatrix<T> read_npy_matrix(const std::filesystem::path& path) {
  const NpyHeader h = read_npy_header(path);
  if (h.shape.size() != 2) fail(path, "expected a 2-D array, got " + std::to_string(h.shape.size()) + "-D");
  const std::size_t rows = h.shape[0], cols = h.shape[1];
  if (rows == 0 || cols == 0) fail(path, "empty array (" + std::to_string(rows) + " x " + std::to_string(cols) + ")");
  const std::size_t item = h.item;
  if (cols > std::numeric_limits<std::size_t>::max() / item / rows) fail(path, "array too large");
  const std::size_t count = rows * cols;

  std::ifstream in(path, std::ios::binary | std::ios::ate);
  const auto end = in.tellg();
  if (end < 0) fail(path, "cannot read file size");
  const auto size = static_cast<std::size_t>(end);
  // read_npy_header checked the sizes already; checked again without a sum that can wrap
  if (size < h.data_offset || (size - h.data_offset) / item < count) {
    fail(path, "truncated data: " + std::to_string(rows) + " x " + std::to_string(cols) + " needs " +
                   std::to_string(count * item) + " bytes");
  }
  in.seekg(static_cast<std::streamoff>(h.data_offset));
  DenseMatrix<T> m(rows, cols);
  // Read in blocks of values, so a large array needs no second copy of itself.
  constexpr std::size_t kBlock = 1 << 16;
  std::vector<unsigned char> raw(std::min(count, kBlock) * item);
  for (std::size_t first = 0; first < count; first += kBlock) {
    const std::size_t n = std::min(kBlock, count - first);
    if (!in.read(reinterpret_cast<char*>(raw.data()), static_cast<std::streamsize>(n * item))) {
      fail(path, "read failed");
    }
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t at = first + k;
      // C order: row after row, as m.values; Fortran order: column after column.
      const std::size_t index = h.fortran_order ? (at % rows) * cols + at / rows : at;
      const double v = value_at(h, raw.data() + k * item);
      if (!std::isfinite(v) || std::abs(v) > static_cast<double>(std::numeric_limits<T>::max())) {
        const std::string where = "row " + std::to_string(index / cols) + ", column " + std::to_string(index % cols);
        fail(path,
             std::isfinite(v) ? "value at " + where + " is too large for float32" : "non-finite value at " + where);
      }
      m.values[index] = static_cast<T>(v);
    }
  }
  return m;
}

template <typename T>
std::string npy_header(const DenseMatrix<T>& matrix) {
  static_assert(std::is_same_v<T, float> || std::is_same_v<T, double>);
  std::string dict = std::string("{'descr': '") + (sizeof(T) == 4 ? "<f4" : "<f8") +
                     "', 'fortran_order': False, 'shape': (" + std::to_string(matrix.rows) + ", " +
                     std::to_string(matrix.cols) + "), }";
  // The whole header (10-byte prefix + dict + padding + '\n') is a multiple of 64 bytes.
  const std::size_t total = ((10 + dict.size() + 1 + 63) / 64) * 64;
  dict.append(total - 10 - dict.size() - 1, ' ');
  dict.push_back('\n');
  std::string out(kMagic, 6);
  out.push_back('\x01');
  out.push_back('\x00');
  const auto len = static_cast<std::uint16_t>(dict.size());
  out.append(reinterpret_cast<const char*>(&len), 2);
  out += dict;
  return out;
}

template <typename T>
std::string_view npy_body(const DenseMatrix<T>& matrix) {
  return {reinterpret_cast<const char*>(matrix.values.data()), matrix.values.size() * sizeof(T)};
}

template <typename T>
std::string encode_npy(const DenseMatrix<T>& matrix) {
  std::string out = npy_header(matrix);
  out += npy_body(matrix);
  return out;
}

template <typename T>
void write_npy(const std::filesystem::path& path, const DenseMatrix<T>& matrix) {
  write_file_atomic(path, encode_npy(matrix));
}

template DenseMatrix<float> read_npy_matrix<float>(const std::filesystem::path&);
template DenseMatrix<double> read_npy_matrix<double>(const std::filesystem::path&);
template std::string npy_header<float>(const DenseMatrix<float>&);
template std::string npy_header<double>(const DenseMatrix<double>&);
template std::string_view npy_body<float>(const DenseMatrix<float>&);
template std::string_view npy_body<double>(const DenseMatrix<double>&);
template std::string encode_npy<float>(const DenseMatrix<float>&);
template std::string encode_npy<double>(const DenseMatrix<double>&);
template void write_npy<float>(const std::filesystem::path&, const DenseMatrix<float>&);
template void write_npy<double>(const std::filesystem::path&, const DenseMatrix<double>&);

}  // namespace seqtopo::io
