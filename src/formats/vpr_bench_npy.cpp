#include "seqtopo/formats/vpr_bench_npy.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>

namespace seqtopo::formats {

namespace {

// The .npy header: its dictionary text and where the data starts.
struct Header {
  std::string_view dict;
  std::size_t data = 0;
};

Header npy_header(std::string_view bytes) {
  if (bytes.size() < 10 || bytes.substr(0, 6) != "\x93NUMPY") throw std::invalid_argument("not a .npy file");
  const auto major = static_cast<unsigned char>(bytes[6]);
  std::size_t length = 0, start = 0;
  if (major == 1) {
    length =
        static_cast<unsigned char>(bytes[8]) | (static_cast<std::size_t>(static_cast<unsigned char>(bytes[9])) << 8);
    start = 10;
  } else if (major == 2 || major == 3) {
    if (bytes.size() < 12) throw std::invalid_argument("truncated .npy header");
    for (int k = 3; k >= 0; --k) length = (length << 8) | static_cast<unsigned char>(bytes[8 + k]);
    start = 12;
  } else {
    throw std::invalid_argument(fmt::format(".npy format version {} is not known", major));
  }
  if (bytes.size() < start + length) throw std::invalid_argument("truncated .npy header");
  return {bytes.substr(start, length), start + length};
}

// A value on the pickle machine's stack: what NumPy's object arrays hold, and the calls that rebuild arrays.
struct Value;
using Ptr = std::shared_ptr<Value>;
struct Value {
  enum class Kind { none, boolean, integer, real, text, list, tuple, dict, global, call, mark } kind = Kind::none;
  std::int64_t integer = 0;
  double real = 0;
  std::string text;        // text and bytes (both kinds: Python 2 writes byte strings for both); global: "mod name"
  std::vector<Ptr> items;  // list, tuple; call: [callable, arguments]
  Ptr state;               // call: what BUILD gave it
};

Ptr make(Value::Kind kind) {
  auto v = std::make_shared<Value>();
  v->kind = kind;
  return v;
}

// The constructors an object array of integers and integer arrays pickles; anything else is refused, so that the
// file is read as data.
bool known_global(const std::string& name) {
  for (const char* module : {"numpy.core.multiarray", "numpy._core.multiarray"}) {
    for (const char* fn : {"_reconstruct", "scalar"}) {
      if (name == std::string(module) + " " + fn) return true;
    }
  }
  return name == "numpy ndarray" || name == "numpy dtype" || name == "__builtin__ object" ||
         name == "builtins object" || name == "copy_reg _reconstructor" || name == "copyreg _reconstructor";
}

class Unpickler {
 public:
  explicit Unpickler(std::string_view bytes) : in_(bytes) {}

  Ptr run() {
    while (true) {
      const auto op = static_cast<unsigned char>(byte());
      switch (op) {
        case 0x80:
          byte();
          break;  // PROTO
        case 0x95:
          fixed(8);
          break;  // FRAME (a length hint)
        case '.':
          return pop();  // STOP
        case '(':
          push(make(Value::Kind::mark));
          break;
        case '0':
          pop();
          break;
        case '1':
          pop_mark();
          break;
        case '2':
          push(top());
          break;
        case 'N':
          push(make(Value::Kind::none));
          break;
        case 0x88:
          push(boolean(true));
          break;
        case 0x89:
          push(boolean(false));
          break;
        case 'J':
          push(integer(static_cast<std::int32_t>(little(4))));
          break;
        case 'K':
          push(integer(static_cast<std::int64_t>(little(1))));
          break;
        case 'M':
          push(integer(static_cast<std::int64_t>(little(2))));
          break;
        case 0x8a:
          push(long_integer(static_cast<std::size_t>(little(1))));
          break;
        case 0x8b:
          push(long_integer(static_cast<std::size_t>(little(4))));
          break;
        case 'I':
          push(text_integer(line()));
          break;
        case 'L':
          push(text_integer(line()));
          break;
        case 'G': {
          std::uint64_t bits = 0;
          for (int k = 0; k < 8; ++k) bits = (bits << 8) | static_cast<unsigned char>(byte());
          double d = 0;
          std::memcpy(&d, &bits, sizeof d);
          auto v = make(Value::Kind::real);
          v->real = d;
          push(v);
          break;
        }
        case 'C':
        case 'U':
        case 0x8c:
          push(text(fixed(little(1))));
          break;
        case 'B':
        case 'T':
        case 'X':
          push(text(fixed(little(4))));
          break;
        case 0x8d:
        case 0x8e:
        case 0x96:
          push(text(fixed(little(8))));
          break;
        case ']':
          push(make(Value::Kind::list));
          break;
        case ')':
          push(make(Value::Kind::tuple));
          break;
        case '}':
          push(make(Value::Kind::dict));
          break;
        case 'l': {
          auto v = make(Value::Kind::list);
          v->items = pop_mark();
          push(v);
          break;
        }
        case 't': {
          auto v = make(Value::Kind::tuple);
          v->items = pop_mark();
          push(v);
          break;
        }
        case 0x85:
        case 0x86:
        case 0x87: {
          auto v = make(Value::Kind::tuple);
          v->items.resize(op - 0x84U);
          for (auto it = v->items.rbegin(); it != v->items.rend(); ++it) *it = pop();
          push(v);
          break;
        }
        case 'a': {
          auto item = pop();
          list_top()->items.push_back(item);
          break;
        }
        case 'e': {
          auto items = pop_mark();
          auto& list = list_top()->items;
          list.insert(list.end(), items.begin(), items.end());
          break;
        }
        case 's':
          pop();
          pop();
          dict_top();
          break;  // SETITEM: dictionaries are not read
        case 'u':
          pop_mark();
          dict_top();
          break;  // SETITEMS
        case 'c': {
          std::string module = line();
          push(global(module + " " + line()));
          break;
        }
        case 0x93: {  // STACK_GLOBAL
          auto name = pop(), module = pop();
          if (name->kind != Value::Kind::text || module->kind != Value::Kind::text)
            throw std::invalid_argument("pickle: STACK_GLOBAL without names");
          push(global(module->text + " " + name->text));
          break;
        }
        case 'R':
        case 0x81: {  // REDUCE, NEWOBJ
          auto args = pop(), callable = pop();
          auto v = make(Value::Kind::call);
          v->items = {callable, args};
          push(v);
          break;
        }
        case 'b': {
          auto state = pop();
          top()->state = state;
          break;
        }
        case 'q':
          memo_[little(1)] = top();
          break;
        case 'r':
          memo_[little(4)] = top();
          break;
        case 0x94:
          memo_[memo_.size()] = top();
          break;
        case 'p':
          memo_[std::stoull(line())] = top();
          break;
        case 'h':
          push(memo(little(1)));
          break;
        case 'j':
          push(memo(little(4)));
          break;
        case 'g':
          push(memo(std::stoull(line())));
          break;
        default:
          throw std::invalid_argument(fmt::format("pickle opcode 0x{:02x} at byte {} is not read", op, pos_));
      }
    }
  }

 private:
  char byte() {
    if (pos_ >= in_.size()) throw std::invalid_argument("pickle: truncated");
    return in_[pos_++];
  }
  std::string_view fixed(std::uint64_t n) {
    if (n > in_.size() - pos_) throw std::invalid_argument("pickle: truncated");
    const auto s = in_.substr(pos_, n);
    pos_ += n;
    return s;
  }
  std::uint64_t little(int n) {
    std::uint64_t v = 0;
    for (int k = 0; k < n; ++k) v |= static_cast<std::uint64_t>(static_cast<unsigned char>(byte())) << (8 * k);
    return v;
  }
  std::string line() {
    const auto end = in_.find('\n', pos_);
    if (end == std::string_view::npos) throw std::invalid_argument("pickle: truncated");
    std::string s(in_.substr(pos_, end - pos_));
    pos_ = end + 1;
    return s;
  }
  static Ptr boolean(bool b) {
    auto v = make(Value::Kind::boolean);
    v->integer = b ? 1 : 0;
    return v;
  }
  static Ptr integer(std::int64_t i) {
    auto v = make(Value::Kind::integer);
    v->integer = i;
    return v;
  }
  Ptr long_integer(std::size_t n) {
    const auto digits = fixed(n);
    if (n > 8) throw std::invalid_argument("pickle: an integer wider than 64 bits");
    std::uint64_t u = 0;
    for (std::size_t k = 0; k < n; ++k)
      u |= static_cast<std::uint64_t>(static_cast<unsigned char>(digits[k])) << (8 * k);
    if (n > 0 && n < 8 && (static_cast<unsigned char>(digits[n - 1]) & 0x80U)) u |= ~std::uint64_t{0} << (8 * n);
    return integer(static_cast<std::int64_t>(u));
  }
  static Ptr text_integer(std::string s) {
    if (!s.empty() && s.back() == 'L') s.pop_back();
    if (s == "00") return boolean(false);
    if (s == "01") return boolean(true);
    try {
      return integer(std::stoll(s));
    } catch (const std::exception&) {
      throw std::invalid_argument("pickle: bad integer '" + s + "'");
    }
  }
  static Ptr text(std::string_view s) {
    auto v = make(Value::Kind::text);
    v->text = s;
    return v;
  }
  static Ptr global(const std::string& name) {
    if (!known_global(name))
      throw std::invalid_argument("pickle: '" + name + "' is not one of the NumPy constructors read");
    auto v = make(Value::Kind::global);
    v->text = name;
    return v;
  }
  void push(Ptr v) { stack_.push_back(std::move(v)); }
  Ptr pop() {
    if (stack_.empty()) throw std::invalid_argument("pickle: stack underflow");
    auto v = stack_.back();
    stack_.pop_back();
    if (v->kind == Value::Kind::mark) throw std::invalid_argument("pickle: unexpected mark");
    return v;
  }
  Ptr top() {
    if (stack_.empty()) throw std::invalid_argument("pickle: stack underflow");
    return stack_.back();
  }
  Ptr list_top() {
    auto v = top();
    if (v->kind != Value::Kind::list) throw std::invalid_argument("pickle: append to a non-list");
    return v;
  }
  void dict_top() {
    if (top()->kind != Value::Kind::dict) throw std::invalid_argument("pickle: set an item of a non-dict");
  }
  std::vector<Ptr> pop_mark() {
    std::vector<Ptr> items;
    while (true) {
      if (stack_.empty()) throw std::invalid_argument("pickle: no mark");
      auto v = stack_.back();
      stack_.pop_back();
      if (v->kind == Value::Kind::mark) break;
      items.push_back(v);
    }
    return {items.rbegin(), items.rend()};
  }
  Ptr memo(std::uint64_t k) {
    const auto it = memo_.find(k);
    if (it == memo_.end()) throw std::invalid_argument("pickle: unknown memo entry");
    return it->second;
  }

  std::string_view in_;
  std::size_t pos_ = 0;
  std::vector<Ptr> stack_;
  std::map<std::uint64_t, Ptr> memo_;
};

bool is_call_of(const Ptr& v, std::string_view suffix) {
  if (v->kind != Value::Kind::call || v->items[0]->kind != Value::Kind::global) return false;
  const auto& name = v->items[0]->text;
  return name.size() >= suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// A NumPy dtype: its kind ('i', 'u', 'f', 'b', 'O'), bytes per value and byte order.
struct Dtype {
  char kind = 'O';
  std::size_t item = 8;
  bool big_endian = false;
};

Dtype dtype_of(const Ptr& v) {
  if (!is_call_of(v, " dtype") || v->items[1]->kind != Value::Kind::tuple || v->items[1]->items.empty() ||
      v->items[1]->items[0]->kind != Value::Kind::text) {
    throw std::invalid_argument("an array without a readable dtype");
  }
  const std::string& name = v->items[1]->items[0]->text;  // 'i8', 'u4', 'f8', 'b1', 'O8'
  Dtype d;
  d.kind = name.empty() ? '?' : name[0];
  d.item = name.size() > 1 ? static_cast<std::size_t>(std::atoi(name.c_str() + 1)) : 0;
  if (v->state && v->state->kind == Value::Kind::tuple && v->state->items.size() > 1 &&
      v->state->items[1]->kind == Value::Kind::text) {
    d.big_endian = v->state->items[1]->text == ">";
  }
  return d;
}

// An ndarray rebuilt by numpy.core.multiarray._reconstruct: shape, dtype, order and data from its state.
struct Array {
  std::vector<std::size_t> shape;
  Dtype dtype;
  bool fortran = false;
  Ptr data;  // bytes, or a list of objects
};

Array array_of(const Ptr& v) {
  if (!is_call_of(v, " _reconstruct") || !v->state || v->state->kind != Value::Kind::tuple ||
      v->state->items.size() != 5) {
    throw std::invalid_argument("not a NumPy array");
  }
  const auto& s = v->state->items;  // (version, shape, dtype, is_fortran, data)
  Array a;
  if (s[1]->kind != Value::Kind::tuple) throw std::invalid_argument("an array without a shape");
  for (const auto& d : s[1]->items) {
    if (d->kind != Value::Kind::integer || d->integer < 0) throw std::invalid_argument("an array with a bad shape");
    a.shape.push_back(static_cast<std::size_t>(d->integer));
  }
  a.dtype = dtype_of(s[2]);
  a.fortran = s[3]->integer != 0;
  a.data = s[4];
  return a;
}

std::size_t index_of(std::int64_t i) {
  if (i < 0) throw std::invalid_argument(fmt::format("a negative index {}", i));
  return static_cast<std::size_t>(i);
}

std::size_t index_of_real(double d) {
  if (!(d >= 0) || d != std::floor(d) || d > 9.0e15)
    throw std::invalid_argument(fmt::format("index {} is not a whole number >= 0", d));
  return static_cast<std::size_t>(d);
}

// The values of a numeric array's raw bytes, as indices.
std::vector<std::size_t> numeric_values(const Dtype& d, std::string_view raw) {
  const bool known = ((d.kind == 'i' || d.kind == 'u') && (d.item == 1 || d.item == 2 || d.item == 4 || d.item == 8)) ||
                     (d.kind == 'f' && (d.item == 4 || d.item == 8));
  if (!known || raw.size() % d.item != 0)
    throw std::invalid_argument(fmt::format("an index array of dtype {}{} is not read", d.kind, d.item));
  std::vector<std::size_t> out;
  for (std::size_t k = 0; k < raw.size(); k += d.item) {
    std::uint64_t u = 0;
    for (std::size_t b = 0; b < d.item; ++b) {
      const auto byte = static_cast<std::uint64_t>(static_cast<unsigned char>(raw[k + b]));
      u |= byte << (8 * (d.big_endian ? d.item - 1 - b : b));
    }
    if (d.kind == 'u') {
      out.push_back(u);
    } else if (d.kind == 'i') {
      if (d.item < 8 && (u >> (8 * d.item - 1)) & 1U) u |= ~std::uint64_t{0} << (8 * d.item);
      out.push_back(index_of(static_cast<std::int64_t>(u)));
    } else if (d.item == 8) {
      double x = 0;
      std::memcpy(&x, &u, 8);
      out.push_back(index_of_real(x));
    } else {
      float x = 0;
      const auto u32 = static_cast<std::uint32_t>(u);
      std::memcpy(&x, &u32, 4);
      out.push_back(index_of_real(x));
    }
  }
  return out;
}

// One entry of a row: an integer, a NumPy integer scalar, a list or tuple of them, or an integer array.
void collect(const Ptr& v, std::vector<std::size_t>& out) {
  switch (v->kind) {
    case Value::Kind::integer:
      out.push_back(index_of(v->integer));
      return;
    case Value::Kind::real:
      out.push_back(index_of_real(v->real));
      return;
    case Value::Kind::list:
    case Value::Kind::tuple:
      for (const auto& item : v->items) collect(item, out);
      return;
    case Value::Kind::call:
      if (is_call_of(v, " scalar")) {  // numpy.int64(5): (dtype, raw bytes)
        const auto& args = v->items[1]->items;
        if (args.size() != 2 || args[1]->kind != Value::Kind::text)
          throw std::invalid_argument("a NumPy scalar without its bytes");
        const auto values = numeric_values(dtype_of(args[0]), args[1]->text);
        out.insert(out.end(), values.begin(), values.end());
        return;
      }
      if (is_call_of(v, " _reconstruct")) {
        const Array a = array_of(v);
        if (a.data->kind == Value::Kind::text) {
          const auto values = numeric_values(a.dtype, a.data->text);
          out.insert(out.end(), values.begin(), values.end());
        } else {
          collect(a.data, out);
        }
        return;
      }
      break;
    default:
      break;
  }
  throw std::invalid_argument("an entry that is not an index nor a list of indices");
}

// The header's 'shape': (a, b, ...).
std::vector<std::size_t> header_shape(std::string_view dict) {
  std::vector<std::size_t> shape;
  const auto at = dict.find("'shape'");
  if (at == std::string_view::npos) return shape;
  const auto open = dict.find('(', at), close = dict.find(')', at);
  if (open == std::string_view::npos || close == std::string_view::npos || close < open) return shape;
  std::size_t value = 0;
  bool digits = false;
  for (char c : dict.substr(open + 1, close - open - 1)) {
    if (c >= '0' && c <= '9') {
      value = value * 10 + static_cast<std::size_t>(c - '0');
      digits = true;
    } else if (c == ',' && digits) {
      shape.push_back(value);
      value = 0;
      digits = false;
    }
  }
  if (digits) shape.push_back(value);
  return shape;
}

}  // namespace

bool npy_holds_objects(std::string_view bytes) {
  try {
    const auto dict = npy_header(bytes).dict;
    const auto at = dict.find("'descr'");
    if (at == std::string_view::npos) return false;
    const auto quote = dict.find('\'', dict.find(':', at));
    return quote != std::string_view::npos && dict.substr(quote + 1, 2) == "|O";
  } catch (const std::invalid_argument&) {
    return false;
  }
}

std::vector<QueryMatches> parse_vpr_bench_npy(std::string_view bytes) {
  const Header header = npy_header(bytes);
  if (!npy_holds_objects(bytes)) throw std::invalid_argument("not an object array (VPR-Bench's form)");
  const Array a = array_of(Unpickler(bytes.substr(header.data)).run());
  if (a.shape.size() != 2 || a.shape[1] != 2 || a.dtype.kind != 'O') {
    std::string shape;
    for (auto d : a.shape) shape += (shape.empty() ? "" : ", ") + std::to_string(d);
    throw std::invalid_argument("expected an object array of shape (queries, 2), got shape (" + shape + ")");
  }
  if (header_shape(header.dict) != a.shape) throw std::invalid_argument("the header's shape is not the array's");
  if (a.data->kind != Value::Kind::list || a.data->items.size() != a.shape[0] * 2)
    throw std::invalid_argument("the array's objects do not match its shape");
  const std::size_t rows = a.shape[0];
  std::vector<QueryMatches> out(rows);
  for (std::size_t r = 0; r < rows; ++r) {
    // C order: row r is items 2r, 2r + 1; Fortran order: the query column first, then the matches column.
    const auto& q = a.data->items[a.fortran ? r : 2 * r];
    const auto& m = a.data->items[a.fortran ? rows + r : 2 * r + 1];
    std::vector<std::size_t> query;
    try {
      collect(q, query);
      if (query.size() != 1) throw std::invalid_argument("the query is not one index");
      out[r].query = query[0];
      collect(m, out[r].maps);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(fmt::format("row {}: {}", r, e.what()));
    }
  }
  return out;
}

}  // namespace seqtopo::formats
