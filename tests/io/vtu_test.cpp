// VTK XML unstructured grids and ParaView collections: round trips, a check by an independent
// reader (Python's xml.etree + base64 + struct), and decode errors.
#include "tear/io/vtu.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "io_fixture.h"
#include "tear/io/atomic_file.h"
#include "tear/io/frames.h"

namespace tear {
namespace {

namespace fs = std::filesystem;

std::string decode_error(const std::string& bytes) { return error_of(decode_vtu, bytes); }

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::path(testing::TempDir()) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(Vtu, RoundTrips3DAnd2DFrames) {
  for (int dim : {2, 3}) {
    const PointTable t = frame_like(dim, 9);
    const PointTable d = decode_vtu(encode_vtu(t));
    ASSERT_EQ(d.count, t.count);
    for (const std::string& name : t.names) EXPECT_EQ(d.column(name), t.column(name)) << name;
    expect_canonical_frame_columns(d);
  }
}

TEST(Vtu, KeepsDoublePrecisionAndOtherNames) {
  PointTable t;
  t.count = 2;
  t.add("x", ColumnType::Float64, {0.1, 0.2});
  t.add("y", ColumnType::Float64, {0.3, 1e-9});
  t.add("drive & <load>", ColumnType::Float64, {1.0 / 3.0, -2});
  t.add("flag", ColumnType::UInt8, {255, 7});
  const PointTable d = decode_vtu(encode_vtu(t));
  EXPECT_EQ(d.names, (std::vector<std::string>{"x", "y", "z", "drive & <load>", "flag"}));
  EXPECT_EQ(d.column("x"), t.column("x"));
  EXPECT_EQ(d.column("y"), t.column("y"));
  EXPECT_EQ(d.column("z"), std::vector<double>(2, 0.0));
  EXPECT_EQ(d.column("drive & <load>"), t.column("drive & <load>"));
  EXPECT_EQ(d.column("flag"), t.column("flag"));
  EXPECT_EQ(d.types[0], ColumnType::Float64);
  EXPECT_EQ(d.types[4], ColumnType::Int32);
}

TEST(Vtu, EmptyTableRoundTrips) {
  const PointTable d = decode_vtu(encode_vtu(frame_like(3, 0)));
  EXPECT_EQ(d.count, 0u);
  EXPECT_EQ(d.names.size(), 12u);
}

TEST(Vtu, DocumentHasTheDeclaredHeaderAndArrays) {
  const std::string s = encode_vtu(frame_like(3, 4));
  EXPECT_NE(s.find("<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
                   "byte_order=\"LittleEndian\" header_type=\"UInt64\">"),
            std::string::npos);
  EXPECT_NE(s.find("<Piece NumberOfPoints=\"4\" NumberOfCells=\"4\">"), std::string::npos);
  for (const char* a :
       {"<DataArray type=\"Int32\" Name=\"id\" format=\"binary\">",
        "<DataArray type=\"Float32\" Name=\"velocity\" NumberOfComponents=\"3\" "
        "format=\"binary\">",
        "<DataArray type=\"Float32\" Name=\"damage\" format=\"binary\">",
        "<DataArray type=\"Int32\" Name=\"material\" format=\"binary\">",
        "<DataArray type=\"Float32\" Name=\"fiber\" NumberOfComponents=\"3\" format=\"binary\">",
        "<DataArray type=\"Float32\" Name=\"Points\" NumberOfComponents=\"3\" format=\"binary\">",
        "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"binary\">",
        "<DataArray type=\"Int64\" Name=\"offsets\" format=\"binary\">",
        "<DataArray type=\"UInt8\" Name=\"types\" format=\"binary\">"})
    EXPECT_NE(s.find(a), std::string::npos) << a;
}

// Python's standard library reads the file on its own: the point count, the arrays and the
// first point's values, the cells.
TEST(Vtu, IndependentParserReadsIt) {
  if (std::system("python3 -c 'import xml.etree.ElementTree, base64, struct' >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "python3 not available";
  const fs::path dir = fresh_dir("tear_vtu_python");
  const std::string file = (dir / "frame.vtu").string();
  write_file_atomic(file, encode_vtu(frame_like(3, 5)));
  const std::string script = R"PY(
import base64, json, struct, sys
import xml.etree.ElementTree as ET
root = ET.parse(sys.argv[1]).getroot()
assert root.tag == "VTKFile" and root.get("type") == "UnstructuredGrid"
assert root.get("header_type") == "UInt64" and root.get("byte_order") == "LittleEndian"
piece = root.find("UnstructuredGrid/Piece")
codes = {"Int32": "i", "Int64": "q", "UInt8": "B", "Float32": "f", "Float64": "d"}
def values(a):
    raw = base64.b64decode("".join(a.text.split()))
    (n,) = struct.unpack("<Q", raw[:8])
    assert len(raw) == 8 + n, (a.get("Name"), len(raw), n)
    code = codes[a.get("type")]
    return list(struct.unpack("<%d%s" % (n // struct.calcsize(code), code), raw[8:]))
out = {"points": int(piece.get("NumberOfPoints")), "cells": int(piece.get("NumberOfCells")),
       "arrays": [], "first": {}}
for a in piece.find("PointData").findall("DataArray"):
    k = int(a.get("NumberOfComponents", "1"))
    out["arrays"].append([a.get("Name"), a.get("type"), k])
    out["first"][a.get("Name")] = values(a)[:k]
out["point0"] = values(piece.find("Points/DataArray"))[:3]
cells = {a.get("Name"): values(a) for a in piece.find("Cells").findall("DataArray")}
out["connectivity"] = cells["connectivity"]
out["offsets"] = cells["offsets"]
out["types"] = cells["types"]
print(json.dumps(out))
)PY";
  const std::string cmd = "python3 -c '" + script + "' " + file + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string text;
  char buf[4096];
  for (size_t got; (got = fread(buf, 1, sizeof(buf), pipe)) > 0;) text.append(buf, got);
  ASSERT_EQ(pclose(pipe), 0) << text;
  const nlohmann::json j = nlohmann::json::parse(text);
  EXPECT_EQ(j["points"], 5);
  EXPECT_EQ(j["cells"], 5);
  EXPECT_EQ(j["arrays"], nlohmann::json::parse(R"([["id", "Int32", 1], ["velocity", "Float32", 3],
      ["damage", "Float32", 1], ["material", "Int32", 1], ["fiber", "Float32", 3]])"));
  EXPECT_EQ(j["point0"], nlohmann::json({0.5, 1.0, 0.75}));
  EXPECT_EQ(j["first"]["id"], nlohmann::json({0}));
  EXPECT_EQ(j["first"]["velocity"], nlohmann::json({-2.0, 3.0, 0.25}));
  EXPECT_EQ(j["first"]["damage"], nlohmann::json({0.0}));
  EXPECT_EQ(j["first"]["fiber"], nlohmann::json({1.0, 0.0, 0.0}));
  EXPECT_EQ(j["connectivity"], nlohmann::json({0, 1, 2, 3, 4}));
  EXPECT_EQ(j["offsets"], nlohmann::json({1, 2, 3, 4, 5}));
  EXPECT_EQ(j["types"], nlohmann::json({1, 1, 1, 1, 1}));
  fs::remove_all(dir);
}

TEST(Vtu, ReadsAsciiArraysAndSeparatelyEncodedHeaders) {
  // ascii arrays, a UInt32 header, and a header base64-encoded apart from its data ("AAA="
  // padding in the middle), as other writers do.
  const std::string doc = R"(<?xml version="1.0"?>
<!-- another writer -->
<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">
  <UnstructuredGrid><Piece NumberOfPoints="2" NumberOfCells="0">
    <PointData>
      <DataArray type="Float64" Name="damage" format="ascii">0.25 1</DataArray>
      <DataArray type="UInt8" Name="m" format="binary">AgAAAA==BwM=</DataArray>
    </PointData>
    <Points><DataArray type="Float32" NumberOfComponents="3" format="ascii">
      1 2 3 4 5 6</DataArray></Points>
    <Cells/>
  </Piece></UnstructuredGrid>
</VTKFile>)";
  const PointTable t = decode_vtu(doc);
  EXPECT_EQ(t.names, (std::vector<std::string>{"x", "y", "z", "damage", "m"}));
  EXPECT_EQ(t.column("z"), (std::vector<double>{3, 6}));
  EXPECT_EQ(t.column("damage"), (std::vector<double>{0.25, 1}));
  EXPECT_EQ(t.column("m"), (std::vector<double>{7, 3}));
  EXPECT_EQ(t.types[4], ColumnType::UInt8);
}

TEST(Vtu, DecodeErrorsAreNamed) {
  const std::string good = encode_vtu(frame_like(3, 4));
  EXPECT_NE(decode_error("").find("no <VTKFile>"), std::string::npos) << decode_error("");
  EXPECT_NE(decode_error("<foo/>").find("root element"), std::string::npos);
  for (size_t cut : {size_t(10), good.size() / 3, good.size() / 2, good.size() - 20}) {
    const std::string why = decode_error(good.substr(0, cut));
    EXPECT_EQ(why.rfind("bad VTU: ", 0), 0u) << cut << ": " << why;
  }
  std::string s = good;
  s.replace(s.find("UnstructuredGrid\""), 16, "PolyData");
  EXPECT_NE(decode_error(s).find("not an unstructured grid"), std::string::npos);
  s = good;
  s.replace(s.find("LittleEndian"), 12, "BigEndian");
  EXPECT_NE(decode_error(s).find("BigEndian"), std::string::npos);
  s = good;
  s.replace(s.find("header_type"), 0, "compressor=\"vtkZLibDataCompressor\" ");
  EXPECT_NE(decode_error(s).find("compressed"), std::string::npos);
  s = good;
  s.replace(s.find("NumberOfPoints=\"4\""), 18, "NumberOfPoints=\"5\"");
  EXPECT_NE(decode_error(s).find("expected 5 points"), std::string::npos) << decode_error(s);
  s = good;
  s.insert(s.find("</DataArray>"), "!");
  EXPECT_NE(decode_error(s).find("base64"), std::string::npos) << decode_error(s);
}

// A document of `points` points at the origin and one ascii point array `w` of `components`.
std::string vtu_with_array(size_t points, const std::string& components, const std::string& w) {
  std::string zeros;
  for (size_t i = 0; i < 3 * points; ++i) zeros += " 0";
  return "<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid><Piece NumberOfPoints=\"" +
         std::to_string(points) + "\"><PointData><DataArray type=\"Float32\" Name=\"w\" " +
         "NumberOfComponents=\"" + components + "\" format=\"ascii\">" + w +
         "</DataArray></PointData><Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" "
         "format=\"ascii\">" + zeros + "</DataArray></Points></Piece></UnstructuredGrid>"
         "</VTKFile>";
}

// Found by fuzzing (tests/fuzz): points x NumberOfComponents was compared with the number of
// values after wrapping around (32 points of 2^59 + 1 components "had" 32 values, then read far
// outside them: a crash), and 10^8 components of no points made 10^8 column names, each checked
// against every earlier one (a hang).
TEST(Vtu, ComponentCountsCannotWrapAroundOrExplode) {
  std::string ones;
  for (int i = 0; i < 32; ++i) ones += " 1";
  EXPECT_EQ(decode_error(vtu_with_array(32, "576460752303423489", ones)),
            "bad VTU: array 'w' has 576460752303423489 components (at most 4096)");
  EXPECT_EQ(decode_error(vtu_with_array(0, "100000000", "")),
            "bad VTU: array 'w' has 100000000 components (at most 4096)");
  EXPECT_EQ(decode_error(vtu_with_array(0, "4094", "")),
            "bad VTU: array 'w' of 4094 components makes more than 4096 columns");
  const PointTable t = decode_vtu(vtu_with_array(0, "4093", ""));
  EXPECT_EQ(t.names.size(), kMaxColumns);
  EXPECT_EQ(decode_vtu(vtu_with_array(2, "2", "1 2 3 4")).column("w_1"),
            (std::vector<double>{2, 4}));
}

TEST(Pvd, ListsTheVtuFramesInOrderWithTheirTimes) {
  const fs::path dir = fresh_dir("tear_pvd");
  fs::create_directories(dir / "frames");
  for (int f : {10, 0, 2})
    write_file_atomic(frame_path(dir.string(), f, "vtu"), encode_vtu(frame_like(2, 1)));
  write_file_atomic(frame_path(dir.string(), 1, "ply"), "ply\n");  // not a vtu frame
  EXPECT_EQ(write_frames_pvd(dir.string(), {{0, 0.0}, {2, 0.04}, {7, 0.14}}), 3u);
  const std::string pvd = read_file((dir / "frames.pvd").string());
  EXPECT_EQ(pvd,
            "<?xml version=\"1.0\"?>\n"
            "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
            "  <Collection>\n"
            "    <DataSet timestep=\"0\" group=\"\" part=\"0\" file=\"frames/00000.vtu\"/>\n"
            "    <DataSet timestep=\"0.04\" group=\"\" part=\"0\" file=\"frames/00002.vtu\"/>\n"
            "    <DataSet timestep=\"10\" group=\"\" part=\"0\" file=\"frames/00010.vtu\"/>\n"
            "  </Collection>\n"
            "</VTKFile>\n");
  fs::remove_all(dir);
}

TEST(Frames, ReadFrameDispatchesOnEveryFormat) {
  const fs::path dir = fresh_dir("tear_frames_formats");
  fs::create_directories(dir / "frames");
  const PointTable t = frame_like(3, 3);
  for (const std::string& f : point_formats())
    write_file_atomic(frame_path(dir.string(), 4, f), encode_points(t, f));
  for (const std::string& f : point_formats()) {
    const PointTable d = read_frame(frame_path(dir.string(), 4, f));
    for (const std::string& name : t.names) EXPECT_EQ(d.column(name), t.column(name)) << f;
    const std::vector<FrameFile> only = list_frames(dir.string(), f);
    ASSERT_EQ(only.size(), 1u);
    EXPECT_EQ(only[0].format, f);
  }
  EXPECT_EQ(list_frames(dir.string()).at(0).format, "ply");  // the preferred one
  try {
    read_frame((dir / "frames" / "00004.obj").string());
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("expected .ply, .bgeo, .vtu"), std::string::npos)
        << e.what();
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace tear
