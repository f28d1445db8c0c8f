// scan3mfExpansion: a tag scanner over the model XML, enough to count objects' triangles and
// component references. It is no XML parser (lib3mf reads the file afterwards, strictly);
// it only has to see what lib3mf would expand.
#include "io/three_mf_scan.h"

#include <minizip/unzip.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <memory>
#include <unordered_map>
#include <vector>

#include "base/errors.h"

namespace frep {

namespace {

struct ObjectCount {
  double triangles = 0;
  std::vector<std::string> components;  // the object ids referenced, once per reference
};

// The value of attribute `name` in the tag text (without the brackets), "" if absent.
std::string attribute(const std::string& tag, const char* name) {
  const std::size_t n = std::char_traits<char>::length(name);
  for (std::size_t at = tag.find(name); at != std::string::npos; at = tag.find(name, at + 1)) {
    if (at == 0 || !std::isspace(static_cast<unsigned char>(tag[at - 1]))) continue;
    std::size_t i = at + n;
    while (i < tag.size() && std::isspace(static_cast<unsigned char>(tag[i]))) ++i;
    if (i >= tag.size() || tag[i] != '=') continue;
    ++i;
    while (i < tag.size() && std::isspace(static_cast<unsigned char>(tag[i]))) ++i;
    if (i >= tag.size() || (tag[i] != '"' && tag[i] != '\'')) continue;
    const std::size_t end = tag.find(tag[i], i + 1);
    if (end == std::string::npos) return "";
    return tag.substr(i + 1, end - i - 1);
  }
  return "";
}

// The tag's local name ("m:object" -> "object"), and whether it closes an element.
std::string localName(const std::string& tag, bool* closing) {
  std::size_t i = 0;
  *closing = !tag.empty() && tag[0] == '/';
  if (*closing) ++i;
  std::size_t end = i;
  while (end < tag.size() && !std::isspace(static_cast<unsigned char>(tag[end])) &&
         tag[end] != '/')
    ++end;
  std::string name = tag.substr(i, end - i);
  const std::size_t colon = name.rfind(':');
  return colon == std::string::npos ? name : name.substr(colon + 1);
}

// A value without the white space round it (XML Schema collapses it before a number's
// pattern applies).
std::string trimmed(const std::string& v) {
  const std::size_t from = v.find_first_not_of(" \t\r\n");
  if (from == std::string::npos) return "";
  return v.substr(from, v.find_last_not_of(" \t\r\n") - from + 1);
}

// The 3MF schema's ST_Number: [+-]?(digits(.digits)?|.digits)([eE][+-]?digits)?. lib3mf 1.8
// reads "one" as 0 and "1abc" as 1, so a file that lies about its coordinates would be
// repaired and written as if it were true.

bool isNumber(const std::string& given) {
  const std::string v = trimmed(given);
  std::size_t i = 0;
  auto digits = [&] {
    const std::size_t from = i;
    while (i < v.size() && std::isdigit(static_cast<unsigned char>(v[i]))) ++i;
    return i > from;
  };
  if (i < v.size() && (v[i] == '+' || v[i] == '-')) ++i;
  const bool whole = digits();
  if (i < v.size() && v[i] == '.') {
    ++i;
    if (!digits()) return false;
  } else if (!whole) {
    return false;
  }
  if (i < v.size() && (v[i] == 'e' || v[i] == 'E')) {
    ++i;
    if (i < v.size() && (v[i] == '+' || v[i] == '-')) ++i;
    if (!digits()) return false;
  }
  return i == v.size();
}

bool isIndex(const std::string& given) {
  const std::string v = trimmed(given);
  return !v.empty() && std::all_of(v.begin(), v.end(),
                                   [](unsigned char c) { return std::isdigit(c) != 0; });
}

// A value for a message: at most 40 characters of it.
std::string quoted(const std::string& v) {
  return "\"" + (v.size() > 40 ? v.substr(0, 40) + "..." : v) + "\"";
}

class Scanner {
 public:
  explicit Scanner(const std::string& shown) : shown_(shown) {}

  void tag(const std::string& text) {
    bool closing = false;
    const std::string name = localName(text, &closing);
    if (name == "object") {
      if (closing) {
        current_ = nullptr;
      } else {
        currentId_ = attribute(text, "id");
        current_ = &objects_[currentId_];
        vertices_ = 0;
        if (!text.empty() && text.back() == '/') current_ = nullptr;
      }
    } else if (closing) {
      return;
    } else if (name == "vertex" && current_) {
      for (const char* axis : {"x", "y", "z"}) {
        const std::string v = attribute(text, axis);
        if (!isNumber(v))
          throw FileError(shown_ + ": vertex " + std::to_string(vertices_) + " of object " +
                          currentId_ + " has " + axis + "=" + quoted(v) +
                          "; a 3MF coordinate is a number (as 1.5, -2, 3e-4)");
      }
      ++vertices_;
    } else if (name == "triangle" && current_) {
      for (const char* corner : {"v1", "v2", "v3"}) {
        const std::string v = attribute(text, corner);
        if (!isIndex(v))
          throw FileError(shown_ + ": triangle " +
                          std::to_string(static_cast<long long>(current_->triangles)) +
                          " of object " + currentId_ + " has " + corner + "=" + quoted(v) +
                          "; a 3MF vertex index is a whole number from 0");
      }
      current_->triangles += 1;
    } else if (name == "component" && current_) {
      current_->components.push_back(attribute(text, "objectid"));
    } else if (name == "item") {
      items_.push_back(attribute(text, "objectid"));
    }
  }

  ThreeMfExpansion total(int maxDepth) {
    const std::string& shown = shown_;
    ThreeMfExpansion sum;
    for (const std::string& id : items_) {
      const ThreeMfExpansion e = expand(id, 0, shown, maxDepth);
      sum.triangles += e.triangles;
      sum.placements += e.placements;
    }
    return sum;
  }

 private:
  ThreeMfExpansion expand(const std::string& id, int depth, const std::string& shown,
                          int maxDepth) {
    if (depth > maxDepth)
      throw FileError(shown + ": components nested deeper than " + std::to_string(maxDepth) +
                      " levels (a cycle or a hostile file)");
    if (auto known = expanded_.find(id); known != expanded_.end()) return known->second;
    ThreeMfExpansion e;
    e.placements = 1;
    auto object = objects_.find(id);
    if (object != objects_.end()) {
      e.triangles = object->second.triangles;
      for (const std::string& child : object->second.components) {
        const ThreeMfExpansion c = expand(child, depth + 1, shown, maxDepth);
        e.triangles += c.triangles;
        e.placements += c.placements;
      }
    }
    expanded_[id] = e;
    return e;
  }

  std::unordered_map<std::string, ObjectCount> objects_;
  std::unordered_map<std::string, ThreeMfExpansion> expanded_;
  std::vector<std::string> items_;
  ObjectCount* current_ = nullptr;
  std::string currentId_;
  std::size_t vertices_ = 0;  // of the current object so far
  const std::string& shown_;
};

bool endsWithModel(const std::string& name) {
  if (name.size() < 6) return false;
  std::string tail = name.substr(name.size() - 6);
  std::transform(tail.begin(), tail.end(), tail.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return tail == ".model";
}

// A tag longer than this is not followed (a hostile file's megabyte of attributes): the
// scanner only needs the short tags it counts.
constexpr std::size_t kLongestTag = 1 << 16;

void scanEntry(unzFile zip, Scanner& scanner) {
  std::vector<char> chunk(1 << 20);
  std::string pending;  // a tag cut by the chunk's end
  bool inTag = false, skipping = false;
  for (;;) {
    const int got = unzReadCurrentFile(zip, chunk.data(), static_cast<unsigned>(chunk.size()));
    if (got <= 0) break;
    const char* at = chunk.data();
    const char* const end = at + got;
    while (at < end) {
      if (!inTag) {  // to the next tag (memchr: a mesh's XML is gigabytes)
        const char* open = static_cast<const char*>(std::memchr(at, '<', std::size_t(end - at)));
        if (!open) break;
        inTag = true;
        skipping = false;
        pending.clear();
        at = open + 1;
        continue;
      }
      const char* close = static_cast<const char*>(std::memchr(at, '>', std::size_t(end - at)));
      const char* stop = close ? close : end;
      if (!skipping) {
        pending.append(at, stop);
        if (pending.size() > kLongestTag) skipping = true;
      }
      if (!close) break;
      if (!skipping) scanner.tag(pending);
      inTag = false;
      at = close + 1;
    }
  }
}

}  // namespace

ThreeMfExpansion scan3mfExpansion(const std::string& file, const std::string& shown,
                                  int maxDepth) {
  std::unique_ptr<void, int (*)(unzFile)> zip(unzOpen64(file.c_str()), unzClose);
  if (!zip) throw FileError(shown + ": not a 3MF package (not a zip archive)");
  Scanner scanner(shown);
  for (int more = unzGoToFirstFile(zip.get()); more == UNZ_OK; more = unzGoToNextFile(zip.get())) {
    char name[1024];
    unz_file_info64 info;
    if (unzGetCurrentFileInfo64(zip.get(), &info, name, sizeof(name), nullptr, 0, nullptr, 0) !=
        UNZ_OK)
      break;
    if (!endsWithModel(name) || unzOpenCurrentFile(zip.get()) != UNZ_OK) continue;
    scanEntry(zip.get(), scanner);
    unzCloseCurrentFile(zip.get());
  }
  return scanner.total(maxDepth);
}

}  // namespace frep
