#include "lom/npy.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>

#include "file_checks.hpp"
#include "lom/atomic_file.hpp"
#include "lom/error.hpp"
#include "lom/images.hpp"

namespace lom {

namespace fs = std::filesystem;

namespace {

constexpr char kMagic[] = "\x93NUMPY";
constexpr size_t kMagicSize = 6;
constexpr const char* kSupportedTypes =
    "one of float32 ('<f4'/'>f4'), float16 ('<f2'/'>f2'), float64 ('<f8'/'>f8'), "
    "uint8 ('|u1'), uint16 ('<u2'/'>u2')";

constexpr bool kHostIsLittleEndian = __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__;

size_t elementSize(NpyType type) {
  switch (type) {
    case NpyType::UInt8:
      return 1;
    case NpyType::Float16:
    case NpyType::UInt16:
      return 2;
    case NpyType::Float32:
      return 4;
    case NpyType::Float64:
      return 8;
  }
  return 1;
}

std::string littleEndianDescr(NpyType type) {
  switch (type) {
    case NpyType::UInt8:
      return "|u1";
    case NpyType::UInt16:
      return "<u2";
    case NpyType::Float16:
      return "<f2";
    case NpyType::Float32:
      return "<f4";
    case NpyType::Float64:
      return "<f8";
  }
  return "<f4";
}

// The header is a Python dict literal such as
// {'descr': '<f4', 'fortran_order': False, 'shape': (480, 640, 3), }
// so a tiny parser for strings, booleans and integer tuples is enough.
struct HeaderValue {
  enum class Kind { String, Bool, Tuple, Other } kind = Kind::Other;
  std::string text;
  bool flag = false;
  std::vector<size_t> numbers;
  std::string source;  // the value as written, for messages
};

class HeaderParser {
 public:
  HeaderParser(std::string text, std::string file)
      : text_(std::move(text)), file_(std::move(file)) {}

  std::map<std::string, HeaderValue> parseDict() {
    std::map<std::string, HeaderValue> dict;
    expect('{');
    while (true) {
      skipSpace();
      if (peek() == '}') break;
      const std::string key = parseString();
      expect(':');
      dict[key] = parseValue();
      skipSpace();
      if (peek() == ',') {
        ++pos_;
        continue;
      }
      expect('}');
      return dict;
    }
    ++pos_;
    return dict;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw Error(file_, "header",
                "a NumPy header dict like {'descr': '<f4', 'fortran_order': False, "
                "'shape': (480, 640)}",
                what + " at character " + std::to_string(pos_) + " of \"" + text_ + "\"");
  }
  void skipSpace() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
  }
  char peek() const { return pos_ < text_.size() ? text_[pos_] : '\0'; }
  void expect(char c) {
    skipSpace();
    if (peek() != c) fail(std::string("'") + c + "' missing");
    ++pos_;
  }
  std::string parseString() {
    skipSpace();
    const char quote = peek();
    if (quote != '\'' && quote != '"') fail("a quoted string missing");
    const size_t end = text_.find(quote, pos_ + 1);
    if (end == std::string::npos) fail("unterminated string");
    std::string value = text_.substr(pos_ + 1, end - pos_ - 1);
    pos_ = end + 1;
    return value;
  }
  size_t parseInteger() {
    skipSpace();
    size_t value = 0;
    const size_t start = pos_;
    while (std::isdigit(static_cast<unsigned char>(peek()))) {
      const size_t digit = static_cast<size_t>(peek() - '0');
      if (value > (std::numeric_limits<size_t>::max() - digit) / 10) fail("dimension too large");
      value = value * 10 + digit;
      ++pos_;
    }
    if (pos_ == start) fail("a non-negative integer dimension missing");
    if (peek() == 'L') ++pos_;  // written by NumPy under Python 2
    return value;
  }
  HeaderValue parseValue() {
    skipSpace();
    const size_t start = pos_;
    HeaderValue value = parseValueAt();
    value.source = text_.substr(start, pos_ - start);
    while (!value.source.empty() && std::isspace(static_cast<unsigned char>(value.source.back())))
      value.source.pop_back();
    if (value.source.size() > 80) value.source = value.source.substr(0, 77) + "...";
    return value;
  }
  HeaderValue parseValueAt() {
    HeaderValue value;
    const char c = peek();
    if (c == '\'' || c == '"') {
      value.kind = HeaderValue::Kind::String;
      value.text = parseString();
    } else if (text_.compare(pos_, 4, "True") == 0 || text_.compare(pos_, 5, "False") == 0) {
      value.kind = HeaderValue::Kind::Bool;
      value.flag = c == 'T';
      pos_ += value.flag ? 4 : 5;
    } else if ((c == '(' || c == '[') && startsIntegerTuple()) {
      value.kind = HeaderValue::Kind::Tuple;
      const char close = c == '(' ? ')' : ']';
      ++pos_;
      while (true) {
        skipSpace();
        if (peek() == close) break;
        value.numbers.push_back(parseInteger());
        skipSpace();
        if (peek() == ',')
          ++pos_;
        else if (peek() != close)
          fail(std::string("',' or '") + close + "' missing");
      }
      ++pos_;
    } else {
      skipNestedValue();
    }
    return value;
  }
  bool startsIntegerTuple() const {
    size_t next = pos_ + 1;
    while (next < text_.size() && std::isspace(static_cast<unsigned char>(text_[next]))) ++next;
    return next < text_.size() && (std::isdigit(static_cast<unsigned char>(text_[next])) ||
                                   text_[next] == ')' || text_[next] == ']');
  }
  // Structured dtypes are lists of tuples; they are rejected later, but the
  // dict must still be walked past them.
  void skipNestedValue() {
    int depth = 0;
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (c == '\'' || c == '"') {
        parseString();
        continue;
      }
      if (c == '(' || c == '[' || c == '{') ++depth;
      if (c == ')' || c == ']' || c == '}') {
        if (depth == 0) return;
        --depth;
      }
      if (c == ',' && depth == 0) return;
      ++pos_;
    }
  }

  std::string text_;
  std::string file_;
  size_t pos_ = 0;
};

std::string numpyTypeName(char kind, const std::string& size) {
  const std::map<char, std::string> kinds = {
      {'f', "float"},      {'u', "uint"},        {'i', "int"},   {'c', "complex"},
      {'b', "bool"},       {'U', "str"},         {'S', "bytes"}, {'O', "object"},
      {'M', "datetime64"}, {'m', "timedelta64"}, {'V', "void"}};
  const auto it = kinds.find(kind);
  if (it == kinds.end()) return "unknown";
  if (kind == 'b' || kind == 'O' || kind == 'M' || kind == 'm') return it->second;
  if (kind == 'U' || kind == 'S' || kind == 'V') return it->second + " of length " + size;
  try {
    const int bytes = std::stoi(size);
    // NumPy names every number type by its total bits: '<c8' is complex64.
    return it->second + std::to_string(bytes * 8);
  } catch (const std::exception&) {
    return it->second;
  }
}

struct Descr {
  NpyType type;
  bool swap;  // stored in the other byte order than the host
};

Descr parseDescr(const std::string& descr, const std::string& file) {
  std::string body = descr;
  char order = '=';
  if (!body.empty() && std::string("<>|=").find(body[0]) != std::string::npos) {
    order = body[0];
    body = body.substr(1);
  }
  const std::map<std::string, NpyType> supported = {{"f4", NpyType::Float32},
                                                    {"f2", NpyType::Float16},
                                                    {"f8", NpyType::Float64},
                                                    {"u1", NpyType::UInt8},
                                                    {"u2", NpyType::UInt16}};
  const auto it = supported.find(body);
  if (it == supported.end()) {
    const std::string name = body.empty() ? "empty" : numpyTypeName(body[0], body.substr(1));
    throw Error(file, "dtype", kSupportedTypes, "'" + descr + "' (" + name + ")");
  }
  const bool file_little = order == '<' || (order != '>' && kHostIsLittleEndian);
  const bool swap = elementSize(it->second) > 1 && file_little != kHostIsLittleEndian;
  return {it->second, swap};
}

void swapBytes(std::vector<std::uint8_t>& bytes, size_t element_size) {
  for (size_t i = 0; i + element_size <= bytes.size(); i += element_size)
    std::reverse(bytes.begin() + static_cast<std::ptrdiff_t>(i),
                 bytes.begin() + static_cast<std::ptrdiff_t>(i + element_size));
}

// Fortran order stores the first index fastest; walk the C-order indices and
// fetch each element from its Fortran offset.
std::vector<std::uint8_t> fortranToC(const std::vector<std::uint8_t>& bytes,
                                     const std::vector<size_t>& shape, size_t element_size) {
  std::vector<std::uint8_t> out(bytes.size());
  const size_t dims = shape.size();
  std::vector<size_t> fortran_stride(dims, 1);
  for (size_t k = 1; k < dims; ++k) fortran_stride[k] = fortran_stride[k - 1] * shape[k - 1];
  std::vector<size_t> index(dims, 0);
  const size_t count = element_size ? bytes.size() / element_size : 0;
  for (size_t c = 0; c < count; ++c) {
    size_t f = 0;
    for (size_t k = 0; k < dims; ++k) f += index[k] * fortran_stride[k];
    std::memcpy(&out[c * element_size], &bytes[f * element_size], element_size);
    for (size_t k = dims; k-- > 0;) {
      if (++index[k] < shape[k]) break;
      index[k] = 0;
    }
  }
  return out;
}

float halfToFloat(std::uint16_t half) {
  const bool negative = (half & 0x8000u) != 0;
  const int exponent = (half >> 10) & 0x1f;
  const int mantissa = half & 0x3ff;
  float value;
  if (exponent == 0) {
    value = std::ldexp(static_cast<float>(mantissa), -24);  // zero and subnormals
  } else if (exponent == 31) {
    value = mantissa == 0 ? std::numeric_limits<float>::infinity()
                          : std::numeric_limits<float>::quiet_NaN();
  } else {
    value = std::ldexp(static_cast<float>(mantissa | 0x400), exponent - 25);
  }
  return negative ? -value : value;
}

std::string shapeText(const std::vector<size_t>& shape) {
  std::string text = "(";
  for (size_t i = 0; i < shape.size(); ++i) text += (i ? ", " : "") + std::to_string(shape[i]);
  return text + (shape.size() == 1 ? ",)" : ")");
}

}  // namespace

size_t NpyArray::size() const {
  size_t count = 1;
  for (size_t dim : shape) count *= dim;
  return count;
}

// Element i of an array converted by `convert(i)`, as an iterator: a vector
// built from two of them writes each float once, where vector(count) would
// first fill millions of zeros (a frame's probability image: 15 MB).
template <class Convert>
class ConvertingIterator {
 public:
  using iterator_category = std::random_access_iterator_tag;
  using value_type = float;
  using difference_type = std::ptrdiff_t;
  using pointer = const float*;
  using reference = float;
  ConvertingIterator(size_t i, const Convert& convert) : i_(i), convert_(&convert) {}
  float operator*() const { return (*convert_)(i_); }
  ConvertingIterator& operator++() {
    ++i_;
    return *this;
  }
  difference_type operator-(const ConvertingIterator& o) const {
    return static_cast<difference_type>(i_) - static_cast<difference_type>(o.i_);
  }
  bool operator==(const ConvertingIterator& o) const { return i_ == o.i_; }
  bool operator!=(const ConvertingIterator& o) const { return i_ != o.i_; }

 private:
  size_t i_;
  const Convert* convert_;
};

template <class Convert>
std::vector<float> convertEach(size_t count, const Convert& convert) {
  return std::vector<float>(ConvertingIterator<Convert>(0, convert),
                            ConvertingIterator<Convert>(count, convert));
}

std::vector<float> NpyArray::toFloat(bool scale_integers) const {
  const size_t count = size();
  const std::uint8_t* data = bytes.data();
  // One conversion per type: a switch inside the loop keeps g++ from
  // vectorising it (a frame's probability image holds millions of values).
  switch (type) {
    case NpyType::Float32: {
      std::vector<float> out(count);
      std::memcpy(out.data(), data, 4 * count);
      return out;
    }
    case NpyType::Float64:
      return convertEach(count, [data](size_t i) {
        double v;
        std::memcpy(&v, data + 8 * i, 8);
        return static_cast<float>(v);
      });
    case NpyType::Float16:
      return convertEach(count, [data](size_t i) {
        std::uint16_t h;
        std::memcpy(&h, data + 2 * i, 2);
        return halfToFloat(h);
      });
    case NpyType::UInt8: {
      std::array<float, 256> value_of{};
      for (int code = 0; code < 256; ++code)
        value_of[static_cast<size_t>(code)] =
            scale_integers ? probabilityOfCode(static_cast<std::uint8_t>(code))
                           : static_cast<float>(code);
      return convertEach(count, [data, &value_of](size_t i) { return value_of[data[i]]; });
    }
    case NpyType::UInt16:
      return convertEach(count, [data, scale_integers](size_t i) {
        std::uint16_t v;
        std::memcpy(&v, data + 2 * i, 2);
        return scale_integers ? static_cast<float>(v / 65535.0) : static_cast<float>(v);
      });
  }
  return std::vector<float>(count);
}

NpyArray readNpy(const fs::path& path) {
  const std::string file = path.string();
  if (const std::string why = notARegularFile(path); !why.empty())
    throw Error(file, "", "an existing .npy file", why);
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw Error(file, "", "a readable .npy file", "cannot open it");
  // One read of the whole file (an iterator over its bytes took longer than
  // decoding the frame's PNGs).
  const std::streamoff file_size = in.tellg();
  if (file_size < 0) throw Error(file, "", "a readable .npy file", "cannot tell its size");
  std::vector<std::uint8_t> raw(static_cast<size_t>(file_size));
  in.seekg(0);
  if (!in.read(reinterpret_cast<char*>(raw.data()), file_size))
    throw Error(file, "", "a readable .npy file",
                "only " + std::to_string(in.gcount()) + " of " + std::to_string(file_size) +
                    " bytes could be read");

  if (raw.size() < kMagicSize || std::memcmp(raw.data(), kMagic, kMagicSize) != 0)
    throw Error(file, "magic", "a NumPy .npy file starting with \\x93NUMPY",
                raw.size() < kMagicSize ? "a file of " + std::to_string(raw.size()) + " bytes"
                                        : "other leading bytes");
  if (raw.size() < kMagicSize + 4)
    throw Error(file, "header", "a format version and header length after \\x93NUMPY",
                "the file ends after " + std::to_string(raw.size()) + " bytes (truncated file)");
  const int major = raw[6];
  const int minor = raw[7];
  if (major < 1 || major > 3 || minor != 0)
    throw Error(file, "version", "format version 1.0, 2.0 or 3.0",
                std::to_string(major) + "." + std::to_string(minor));
  size_t header_length = 0;
  size_t header_start = 0;
  if (major == 1) {
    header_length = raw[8] | (static_cast<size_t>(raw[9]) << 8);
    header_start = 10;
  } else {
    if (raw.size() < 12) throw Error(file, "header", "a complete header", "the file ends early");
    header_length = raw[8] | (static_cast<size_t>(raw[9]) << 8) |
                    (static_cast<size_t>(raw[10]) << 16) | (static_cast<size_t>(raw[11]) << 24);
    header_start = 12;
  }
  if (raw.size() < header_start + header_length)
    throw Error(file, "header", std::to_string(header_length) + " header bytes",
                std::to_string(raw.size() - header_start) + " bytes (truncated file)");
  const std::string header(raw.begin() + static_cast<std::ptrdiff_t>(header_start),
                           raw.begin() + static_cast<std::ptrdiff_t>(header_start + header_length));
  const auto dict = HeaderParser(header, file).parseDict();

  const auto descr = dict.find("descr");
  if (descr == dict.end()) throw Error(file, "header", "a 'descr' entry", "none");
  if (descr->second.kind != HeaderValue::Kind::String)
    throw Error(file, "dtype", kSupportedTypes, "a structured dtype");
  // What an entry of the wrong kind holds, as written; "none" when it is absent.
  const auto found = [&](const auto& entry) {
    if (entry == dict.end()) return std::string("none");
    return (entry->second.kind == HeaderValue::Kind::String ? "the string " : "") +
           entry->second.source;
  };
  const auto fortran = dict.find("fortran_order");
  if (fortran == dict.end() || fortran->second.kind != HeaderValue::Kind::Bool)
    throw Error(file, "header", "a 'fortran_order' entry of True or False", found(fortran));
  const auto shape = dict.find("shape");
  if (shape == dict.end() || shape->second.kind != HeaderValue::Kind::Tuple)
    throw Error(file, "header", "a 'shape' entry with a tuple of non-negative integers",
                found(shape));

  const Descr parsed = parseDescr(descr->second.text, file);
  NpyArray array;
  array.type = parsed.type;
  array.shape = shape->second.numbers;

  const size_t element_size = elementSize(array.type);
  const size_t available = raw.size() - header_start - header_length;
  size_t count = 1;
  for (size_t dim : array.shape) {
    if (dim != 0 && count > std::numeric_limits<size_t>::max() / element_size / dim)
      throw Error(file, "shape", "a shape that fits in memory", shapeText(array.shape));
    count *= dim;
  }
  const size_t needed = count * element_size;
  if (available != needed)
    throw Error(file, "data",
                std::to_string(needed) + " data bytes for shape " + shapeText(array.shape) +
                    " of " + descr->second.text,
                std::to_string(available) + " bytes" +
                    (available < needed ? " (truncated file)" : " (extra bytes at the end)"));

  // The data moves to the front of the buffer read, instead of into a copy.
  raw.erase(raw.begin(), raw.begin() + static_cast<std::ptrdiff_t>(header_start + header_length));
  array.bytes = std::move(raw);
  if (parsed.swap) swapBytes(array.bytes, element_size);
  if (fortran->second.flag && array.shape.size() > 1)
    array.bytes = fortranToC(array.bytes, array.shape, element_size);
  return array;
}

void writeNpy(const fs::path& path, const NpyArray& array) {
  const size_t element_size = elementSize(array.type);
  if (array.bytes.size() != array.size() * element_size)
    throw Error(
        path.string(), "data",
        std::to_string(array.size() * element_size) + " bytes for shape " + shapeText(array.shape),
        std::to_string(array.bytes.size()) + " bytes");
  std::string header = "{'descr': '" + littleEndianDescr(array.type) +
                       "', 'fortran_order': False, 'shape': " + shapeText(array.shape) + ", }";
  // NumPy pads the header with spaces and a newline so the data starts on a
  // 64-byte boundary; readers that memory-map rely on that alignment.
  const bool version2 = header.size() + 1 + kMagicSize + 4 > 65535;
  const size_t prefix = kMagicSize + 2 + (version2 ? 4 : 2);
  const size_t total = (prefix + header.size() + 1 + 63) / 64 * 64;
  header.append(total - prefix - header.size() - 1, ' ');
  header += '\n';

  std::vector<std::uint8_t> bytes = array.bytes;
  if (!kHostIsLittleEndian && element_size > 1) swapBytes(bytes, element_size);

  writeFileAtomically(path, [&](std::ostream& out) {
    out.write(kMagic, kMagicSize);
    out.put(static_cast<char>(version2 ? 2 : 1));
    out.put(0);
    const size_t length = header.size();
    const int length_bytes = version2 ? 4 : 2;
    for (int i = 0; i < length_bytes; ++i) out.put(static_cast<char>((length >> (8 * i)) & 0xff));
    out.write(header.data(), static_cast<std::streamsize>(header.size()));
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
  });
}

void writeNpyFloat32(const fs::path& path, const std::vector<size_t>& shape,
                     const std::vector<float>& values) {
  NpyArray array;
  array.type = NpyType::Float32;
  array.shape = shape;
  array.bytes.resize(values.size() * sizeof(float));
  std::memcpy(array.bytes.data(), values.data(), array.bytes.size());
  writeNpy(path, array);
}

}  // namespace lom
