#include "core/atomic_file.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include "core/errors.h"
#include "core/limits.h"

namespace fs = std::filesystem;

namespace volts::core {

void write_atomically(const std::string& path, const std::function<void(const std::string&)>& write) {
  const fs::path target(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir)) throw IoError(path + ": cannot create directory " + dir.string());
  // Same directory, so rename() is atomic; pid in the name keeps concurrent writers apart.
  const fs::path tmp = dir / ("." + target.filename().string() + ".tmp" + std::to_string(::getpid()));
  try {
    write(tmp.string());
  } catch (...) {
    fs::remove(tmp, ec);
    throw;
  }
  if (!fs::exists(tmp)) throw IoError(path + ": writer produced no file");
  fs::rename(tmp, target, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw IoError(path + ": cannot rename temporary file into place: " + ec.message());
  }
}

void write_text_atomically(const std::string& path, const std::string& content) {
  write_atomically(path, [&](const std::string& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) throw IoError(path + ": cannot open for writing");
    out << content;
    out.close();
    if (!out) throw IoError(path + ": write failed (disk full?)");
  });
}

std::string read_text_file(const std::string& path) {
  if (fs::is_directory(path)) throw InvalidInputError(path + ": is a directory, expected a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InvalidInputError(path + ": cannot open file (does it exist?)");
  std::error_code ec;
  const auto size = fs::file_size(path, ec);
  if (!ec && size > physical_memory_bytes() / 2)
    throw InvalidInputError(path + ": is " + std::to_string(size) + " bytes, more than this machine can hold (limit " +
                            std::to_string(physical_memory_bytes() / 2) + ")");
  if (!ec) {
    // One read into a string of the file's size (a stringstream copy touched every page twice).
    std::string text(static_cast<std::size_t>(size), '\0');
    in.read(text.data(), static_cast<std::streamsize>(size));
    if (static_cast<std::uintmax_t>(in.gcount()) == size && in.peek() == std::char_traits<char>::eof()) return text;
    in.clear();
    in.seekg(0);
  }
  std::ostringstream s;  // size unknown, or the file changed while read
  s << in.rdbuf();
  return s.str();
}

}  // namespace volts::core
