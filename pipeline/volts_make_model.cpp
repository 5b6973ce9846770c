// volts-make-model — writes one of the generated test solids of volts::models as a surface file.
//
//   volts-make-model NAME [--resolution N] [--bulge B] -o FILE     (also --list, --help)
#include <iostream>
#include <sstream>
#include <string>

#include "core/errors.h"
#include "models/models.h"
#include "surface/surface.h"

namespace {

using volts::core::UsageError;

const char* const kTool = "volts-make-model";

void print_help(std::ostream& out) {
  const volts::models::ModelParams defaults;
  out << "usage: " << kTool << " NAME [--resolution N] [--bulge B] -o FILE\n"
      << "       " << kTool << " --list | --help\n\n"
      << "Writes a generated test solid as a closed triangle mesh (.off, .obj, .stl or .ply by extension).\n\n"
      << "options:\n"
      << "  --resolution N  segments along the longest edge or around the smallest circle, 4..512 (default "
      << defaults.resolution << ")\n"
      << "  --bulge B       bulged-box: outward bulge of each face centre, relative to half the face's shorter\n"
      << "                  side, 0..0.35 (default " << defaults.bulge << ")\n"
      << "  -o FILE         output file, written atomically\n"
      << "  --list          print the model names and descriptions\n\n"
      << "models:\n";
  for (const auto& name : volts::models::model_names())
    out << "  " << name << std::string(name.size() < 16 ? 16 - name.size() : 1, ' ')
        << volts::models::model_description(name) << "\n";
}

/// Parses the whole of `text` as a T (int or double); throws UsageError naming the option otherwise.
template <typename T>
T parse_number(const std::string& option, const std::string& text) {
  std::istringstream in(text);
  T value{};
  if (!(in >> value) || !(in >> std::ws).eof())
    throw UsageError(option + " expects a number, got '" + text + "'");
  return value;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    volts::models::ModelParams params;
    std::string output;
    bool have_name = false;
    for (int i = 1; i < argc; ++i) {
      const std::string arg = argv[i];
      const auto value = [&]() -> std::string {
        if (i + 1 >= argc) throw UsageError(arg + " needs a value");
        return argv[++i];
      };
      if (arg == "--help" || arg == "-h") {
        print_help(std::cout);
        return 0;
      }
      if (arg == "--list") {
        for (const auto& name : volts::models::model_names())
          std::cout << name << "\t" << volts::models::model_description(name) << "\n";
        return 0;
      }
      if (arg == "--resolution") {
        params.resolution = parse_number<int>(arg, value());
      } else if (arg == "--bulge") {
        params.bulge = parse_number<double>(arg, value());
      } else if (arg == "-o" || arg == "--output") {
        output = value();
      } else if (arg.size() > 1 && arg[0] == '-') {
        throw UsageError("unknown option '" + arg + "' (see --help)");
      } else if (have_name) {
        throw UsageError("more than one model name: '" + params.name + "' and '" + arg + "'");
      } else {
        params.name = arg;
        have_name = true;
      }
    }
    if (!have_name) throw UsageError("no model name given (see --list)");
    if (output.empty()) throw UsageError("no output file given (-o FILE)");

    const volts::surface::Mesh mesh = volts::models::make_model(params);
    volts::surface::write_surface(output, mesh);
    std::cout << params.name << ": " << mesh.number_of_vertices() << " vertices, " << mesh.number_of_faces()
              << " faces, genus " << volts::surface::genus(mesh) << ", volume "
              << volts::surface::signed_volume(mesh) << " -> " << output << "\n";
    return 0;
  } catch (const volts::core::Error& e) {
    std::cerr << kTool << ": error: " << e.what() << "\n";
    return e.exit_code();
  } catch (const std::exception& e) {
    std::cerr << kTool << ": error: internal: " << e.what() << "\n";
    return static_cast<int>(volts::core::ExitCode::internal);
  }
}
