// The readers as fuzzing entry points (see fuzz_entry.h).
#include "fuzz_entry.h"

#include <unistd.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "core/error.h"
#include "io/mesh_io.h"
#include "mesh/build.h"
#include "mesh/surface_mesh.h"

namespace anisurf::fuzz {
namespace {

namespace fs = std::filesystem;

struct ReaderInfo {
  Reader reader;
  const char* name;
  const char* extension;
};

constexpr ReaderInfo kReaders[] = {
    {Reader::Medit, "medit", ".mesh"}, {Reader::MeditBinary, "meshb", ".meshb"}, {Reader::Sol, "sol", ".sol"},
    {Reader::SolBinary, "solb", ".solb"}, {Reader::Obj, "obj", ".obj"},        {Reader::Off, "off", ".off"},
    {Reader::Ply, "ply", ".ply"},       {Reader::Stl, "stl", ".stl"},            {Reader::Gltf, "gltf", ".gltf"},
    {Reader::Glb, "glb", ".glb"},       {Reader::Gmsh, "msh", ".msh"},           {Reader::Vtu, "vtu", ".vtu"},
    {Reader::Vtp, "vtp", ".vtp"},       {Reader::Vtk, "vtk", ".vtk"},
};

const ReaderInfo& info(Reader r) {
  for (const ReaderInfo& i : kReaders)
    if (i.reader == r) return i;
  return kReaders[0];
}

// A directory of this process for the inputs, removed at exit.
class ScratchDirectory {
 public:
  ScratchDirectory() : dir_(fs::temp_directory_path() / ("anisurf_fuzz_" + std::to_string(::getpid()))) {
    fs::create_directories(dir_);
  }
  ~ScratchDirectory() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  // The input file of reader r, alone in its directory (a glTF's buffer URIs
  // then only find files the input names itself).
  fs::path input(Reader r) const {
    const fs::path d = dir_ / info(r).name;
    fs::create_directories(d);
    return d / (std::string("input") + info(r).extension);
  }

 private:
  fs::path dir_;
};

const ScratchDirectory& scratch() {
  static const ScratchDirectory dir;
  return dir;
}

// Builds the mesh as a user's load does, and once more with every format's
// vertices welded within a tolerance (the grid hash of merge_positions).
Result build_and_validate(const MeshData& data, const std::string& path) {
  BuildOptions welded;
  welded.merge = BuildOptions::Merge::Always;
  welded.merge_tolerance = 1e-6;
  for (const BuildOptions& options : {BuildOptions{}, welded}) {
    SurfaceMesh mesh;
    build_mesh(data, mesh, options, path);
    const ValidationReport report = mesh.validate();
    if (!report.ok()) return {Outcome::Invalid, report.summary()};
  }
  return {};
}

Result check_fields(const std::vector<FieldData>& fields) {
  std::size_t vertices = 0;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    const FieldData& f = fields[i];
    const auto nc = static_cast<std::size_t>(f.info.ncomp);
    if (nc < 1 || nc > 6 || f.values.size() % nc != 0)
      return {Outcome::Invalid, "field " + std::to_string(i) + ": " + std::to_string(f.values.size()) +
                                    " values of " + std::to_string(nc) + " components"};
    if (i == 0) vertices = f.values.size() / nc;
    if (f.values.size() / nc != vertices)
      return {Outcome::Invalid, "field " + std::to_string(i) + " has another vertex count than field 0"};
  }
  return {};
}

Result read_path(Reader r, const std::string& path) {
  try {
    if (r == Reader::Sol || r == Reader::SolBinary) return check_fields(read_sol(path, -1));
    return build_and_validate(read_mesh_data(path), path);
  } catch (const Error& e) {
    return {Outcome::Refused, e.what()};
  }
}

}  // namespace

const std::vector<Reader>& all_readers() {
  static const std::vector<Reader> readers = [] {
    std::vector<Reader> v;
    for (const ReaderInfo& i : kReaders) v.push_back(i.reader);
    return v;
  }();
  return readers;
}

const char* reader_name(Reader r) { return info(r).name; }
const char* reader_extension(Reader r) { return info(r).extension; }

std::optional<Reader> reader_of(const std::string& file_name) {
  std::string ext = fs::path(file_name).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (const ReaderInfo& i : kReaders)
    if (ext == i.extension) return i.reader;
  return std::nullopt;
}

Result read_bytes(Reader r, const std::uint8_t* data, std::size_t size) {
  const fs::path input = scratch().input(r);
  {
    std::ofstream out(input, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  return read_path(r, input.string());
}

Result read_file(Reader r, const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return read_bytes(r, reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
}

}  // namespace anisurf::fuzz
