// What a run file tells other tools about itself: a "units" attribute on every dataset RunWriter
// writes, and the XDMF sidecar <run>.xdmf with which ParaView opens the run as a time series.
// The sidecar is checked here for well-formed XML whose HDF5 references exist with the stated
// shapes and whose times are the run's.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "cli_child.h"
#include "io/h5_util.h"
#include "io/run_reader.h"
#include "synthetic_run.h"

namespace {

namespace fs = std::filesystem;

// Tags balance and nest, attribute values are quoted, comments hold no "--": enough to catch a
// broken writer. Names may carry a namespace prefix (xi:include).
void expect_well_formed_xml(std::string xml) {
  const size_t decl = xml.find("?>");
  ASSERT_EQ(xml.rfind("<?xml", 0), 0u) << "no XML declaration";
  ASSERT_NE(decl, std::string::npos);
  for (size_t c = xml.find("<!--"); c != std::string::npos; c = xml.find("<!--")) {
    const size_t end = xml.find("-->", c + 4);
    ASSERT_NE(end, std::string::npos) << "an unclosed comment";
    EXPECT_EQ(xml.substr(c + 4, end - c - 4).find("--"), std::string::npos) << "'--' in a comment";
    xml.erase(c, end + 3 - c);
  }
  const std::string body = xml.substr(decl + 2);
  const std::regex tag_re(R"(<(/?)([A-Za-z_][\w.:-]*)((?:\s+[\w.:-]+="[^"<&]*")*)\s*(/?)>)");
  std::vector<std::string> open;
  size_t last = 0;  // end of the previous tag: text in between must hold no markup
  for (auto it = std::sregex_iterator(body.begin(), body.end(), tag_re);
       it != std::sregex_iterator(); ++it) {
    const std::smatch& m = *it;
    const std::string text = body.substr(last, static_cast<size_t>(m.position()) - last);
    EXPECT_EQ(text.find_first_of("<>"), std::string::npos) << "malformed markup: " << text;
    last = static_cast<size_t>(m.position() + m.length());
    if (m[1] == "/") {
      ASSERT_FALSE(open.empty()) << "closing " << m[2] << " with nothing open";
      EXPECT_EQ(open.back(), m[2]);
      open.pop_back();
    } else if (m[4] != "/") {
      open.push_back(m[2]);
    }
  }
  EXPECT_EQ(body.substr(last).find_first_not_of(" \n"), std::string::npos) << "text after the root";
  EXPECT_TRUE(open.empty()) << open.size() << " tags left open";
}

TEST(RunFileForOtherTools, EveryDatasetHasUnitsAndTheXdmfSidecarMatchesTheFile) {
  const fs::path dir = nsf::testing::fresh_dir("units_xdmf");
  const std::string run = (dir / "drop.h5").string();
  nsf::testing::write_synthetic_run(run, 3);

  const std::map<std::string, std::string> units = {
      {"/X", "m"},        {"/mass", "kg"},       {"/volume", "m^3"},   {"/material", "1"},
      {"/object", "1"},   {"/frames/x", "m"},    {"/frames/v", "m/s"}, {"/frames/C", "1/s"},
      {"/frames/F", "1"}, {"/frames/tau", "Pa"}, {"/frames/time", "s"}};
  const hid_t file = H5Fopen(run.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  for (const auto& [name, unit] : units) {
    const hid_t set = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
    ASSERT_GE(set, 0) << name;
    EXPECT_EQ(nsf::h5::read_attribute_string(set, "units", run), unit) << name;
    H5Dclose(set);
  }

  const fs::path xdmf = dir / "drop.xdmf";
  ASSERT_TRUE(fs::exists(xdmf));
  EXPECT_FALSE(fs::exists(dir / "drop.xdmf.tmp"));
  const std::string xml = nsf::testing::read_text(xdmf.string());
  expect_well_formed_xml(xml);

  // Every HDF5 reference names this file and a dataset of exactly the stated shape.
  const std::regex hdf_re(
      R"re(<DataItem Dimensions="([0-9 ]+)"[^>]*Format="HDF">([^:<]+):([^<]+)</DataItem>)re");
  size_t refs = 0;
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), hdf_re); it != std::sregex_iterator();
       ++it, ++refs) {
    EXPECT_EQ((*it)[2], "drop.h5");
    const std::vector<hsize_t> shape = nsf::h5::dataset_shape(file, (*it)[3], run);
    std::string dims;
    for (hsize_t d : shape) dims += (dims.empty() ? "" : " ") + std::to_string(d);
    EXPECT_EQ((*it)[1], dims) << (*it)[3];
  }
  H5Fclose(file);
  EXPECT_EQ(refs, 3u * 10u);  // per frame: x, v, C, F, tau and the 5 static datasets

  // A temporal collection: one grid per frame at the run's times, each a Polyvertex cloud.
  const nsf::RunReader reader(run);
  const std::regex time_re(R"re(<Time Value="([^"]+)"/>)re");
  std::vector<double> times;
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), time_re);
       it != std::sregex_iterator(); ++it)
    times.push_back(std::stod((*it)[1]));
  EXPECT_EQ(times, reader.times());
  EXPECT_NE(xml.find("CollectionType=\"Temporal\""), std::string::npos);
  // One Polyvertex topology with the connectivity 0..P-1 (in the first grid), which every other
  // grid includes: without connectivity the Xdmf3 library makes no cells.
  const size_t p = reader.particle_count();
  const std::string topology = "<Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" +
                               std::to_string(p) + "\" NodesPerElement=\"1\">";
  const size_t at = xml.find(topology);
  ASSERT_NE(at, std::string::npos);
  EXPECT_EQ(xml.find(topology, at + 1), std::string::npos);
  const size_t values = xml.find('>', xml.find("<DataItem", at)) + 1;
  std::istringstream connectivity(xml.substr(values, xml.find("</DataItem>", values) - values));
  size_t next = 0;
  for (size_t i; connectivity >> i; ++next) EXPECT_EQ(i, next);
  EXPECT_EQ(next, p);
  const std::string include =
      "<xi:include xpointer=\"xpointer(/Xdmf/Domain/Grid/Grid[1]/Topology)\"/>";
  size_t includes = 0;
  for (size_t i = xml.find(include); i != std::string::npos; i = xml.find(include, i + 1))
    ++includes;
  EXPECT_EQ(includes, reader.frame_count() - 1);
  // The arrays carry the export formats' names (docs/VISUALISE.md).
  for (const char* name : {"v", "C", "F", "tau", "X", "mass", "volume", "material", "object"})
    EXPECT_NE(xml.find("<Attribute Name=\"" + std::string(name) + "\""), std::string::npos) << name;
  fs::remove_all(dir);
}

}  // namespace
