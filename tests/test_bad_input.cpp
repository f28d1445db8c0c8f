// Malformed and hostile input, every class the architecture issue lists: one clear message
// naming the file, the object, the parameter and what is allowed; never a crash, a hang or a
// library's own exception text.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "base/errors.h"
#include "base/exit_status.h"
#include "check/mesh_check.h"
#include "frep/formula.h"
#include "frep/model_json.h"
#include "io/mesh_io.h"

namespace frep {
namespace {

namespace fs = std::filesystem;

// The message of the ModelError (or FileError) that `f` throws; fails when none is thrown.
template <class F>
std::string messageOf(F f) {
  try {
    f();
  } catch (const ModelError& e) {
    return e.what();
  } catch (const FileError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error thrown";
  return "";
}

void expectHas(const std::string& message, const std::string& part) {
  EXPECT_NE(message.find(part), std::string::npos) << "message: " << message;
  // nlohmann's own exception text must never reach the user
  EXPECT_EQ(message.find("json.exception"), std::string::npos) << message;
}

std::string parseError(const std::string& text) {
  return messageOf([&] { parseModel(text, "part.json"); });
}

// One mapping from errors to exit statuses: the user's mistakes are bad input, a cancel is
// 130, anything else is a bug (3), never 2.
TEST(ExitStatus, EachErrorKindHasItsStatusAndOneLine) {
  auto outcome = [](auto error, std::string* line) {
    return outcomeOf(std::make_exception_ptr(error), line);
  };
  std::string line;
  EXPECT_EQ(outcome(ModelError("sphere: parameter 'radius' = -1"), &line), Outcome::BadInput);
  EXPECT_EQ(line, "sphere: parameter 'radius' = -1");
  EXPECT_EQ(outcome(FileError("x.stl: no such file"), &line), Outcome::BadInput);
  EXPECT_EQ(outcome(TooLargeError("too large"), &line), Outcome::BadInput);
  // a solid with no point inside is a verdict on the result, as a failed check is
  EXPECT_EQ(outcome(EmptySolidError("the solid is empty"), &line), Outcome::NotPrintable);
  EXPECT_EQ(exitStatus(Outcome::NotPrintable), 1);
  EXPECT_EQ(outcome(Cancelled(), &line), Outcome::Cancelled);
  EXPECT_EQ(exitStatus(Outcome::Cancelled), 130);
  EXPECT_EQ(outcome(std::bad_alloc(), &line), Outcome::BadInput);
  EXPECT_NE(line.find("out of memory"), std::string::npos);
  EXPECT_EQ(outcome(std::logic_error("vector::at"), &line), Outcome::InternalError);
  EXPECT_EQ(exitStatus(Outcome::InternalError), 3);
  EXPECT_EQ(line, "internal error (a bug: please report it): vector::at");
  EXPECT_EQ(outcome(42, &line), Outcome::InternalError);
}

TEST(BadModel, UnknownKeysAndFormatVersions) {
  expectHas(parseError(R"({"root": {"type": "sphere"}, "exprot": {}})"),
            "part.json: unknown key \"exprot\"; a model file has \"frepcad\"");
  expectHas(parseError(R"({"frepcad": 99, "root": {"type": "sphere"}})"),
            "part.json: \"frepcad\": 99 is not a format version this frepcad reads; allowed: 1");
  expectHas(parseError(R"({"frepcad": "1", "root": {"type": "sphere"}})"), "allowed: 1");
  expectHas(parseError(R"({"root": {"type": "sphere"}, "export": {"resolutoin": 0.1}})"),
            "export: unknown key \"resolutoin\"");
  expectHas(parseError(R"({"root": {"type": "sphere", "parms": {}}})"), "unknown key \"parms\"");
}

TEST(BadModel, MalformedJsonInOurWords) {
  expectHas(parseError(R"({"root": {"type": "sphere", "params": {"radius": NaN}}})"),
            "not valid JSON at line 1, column 50: NaN and Infinity are not JSON numbers");
  expectHas(parseError(R"({"root": {"type": "sphere", "params": {"radius": Infinity}}})"),
            "NaN and Infinity are not JSON numbers");
  expectHas(parseError(R"({"root": {"type": "sphere", "params": {"radius": 1e999}}})"),
            "beyond the range of double");
  expectHas(parseError("{\"root\": {\"type\": \"sph"), "ends in the middle of a value");
  expectHas(parseError("{\"root\": {\"type\": \"sph\xff\xfe\"}}"), "not UTF-8");
  expectHas(parseError("{\"root\":\n {\"type\" \"sphere\"}}"), "not valid JSON at line 2");
  expectHas(parseError(R"({"root": {"type": "sphere", "params": {"radius": "big"}}})"),
            "parameter 'radius' expects");
}

TEST(BadModel, DeepTreesAndRefChainsAreRefusedNotOverflowed) {
  // 100,000 nested translates
  std::string deep;
  for (int i = 0; i < 100000; ++i) deep += R"({"type": "translate", "inputs": [)";
  deep += R"({"type": "sphere"})";
  for (int i = 0; i < 100000; ++i) deep += "]}";
  expectHas(parseError("{\"root\": " + deep + "}"), "nested deeper than 1000");
  // a chain of 10,000 refs
  std::string defs;
  for (int i = 0; i < 10000; ++i)
    defs += "\"d" + std::to_string(i) + "\": {\"type\": \"translate\", \"inputs\": [{\"ref\": \"d" +
            std::to_string(i + 1) + "\"}]},";
  defs += R"("d10000": {"type": "sphere"})";
  expectHas(parseError(R"({"root": {"ref": "d0"}, "definitions": {)" + defs + "}}"),
            "nested deeper than 1000");
  // a cycle
  expectHas(parseError(R"({"root": {"ref": "a"}, "definitions": {"a": {"type": "complement",
            "inputs": [{"ref": "b"}]}, "b": {"type": "complement", "inputs": [{"ref": "a"}]}}})"),
            "cycle");
  // in code: the same limit, at the node that would pass it
  NodePtr n = makeNode("sphere", {}, {});
  std::string message;
  try {
    for (int i = 0; i < 5000; ++i) n = makeNode("complement", {}, {n});
  } catch (const ModelError& e) {
    message = e.what();
  }
  expectHas(message, "nested deeper than 1000 nodes");
}

TEST(BadModel, WideUnionsAreFine) {
  std::string inputs;
  for (int i = 0; i < 100000; ++i)
    inputs += std::string(i ? "," : "") + "{\"type\": \"sphere\", \"params\": {\"center\": [" +
              std::to_string(i) + ", 0, 0], \"radius\": 0.4}}";
  const Model m = parseModel(R"({"root": {"type": "union", "inputs": [)" + inputs + "]}}");
  const Program p = compile(m.root);
  EXPECT_NEAR(p.eval(77777, 0, 0), 0.4, 1e-12);
}

TEST(BadModel, HostileFormulas) {
  const std::string nested = std::string(1000000, '(') + "x" + std::string(1000000, ')');
  expectHas(messageOf([&] {
              makeNode("formula", {{"formula", textValue(nested)}}, {}, "root");
            }),
            "nested deeper than 500 levels");
  expectHas(
      messageOf([&] {
        makeNode("formula", {{"formula", textValue(std::string(1000000, '-') + "x")}}, {}, "root");
      }),
      "nested deeper than 500 levels");
  // a long flat sum is not nesting: it compiles (iteratively) and evaluates
  std::string sum = "1 - sqrt(x*x + y*y + z*z)";
  for (int i = 0; i < 100000; ++i) sum += " + 0*x";
  const Program p = compile(makeNode("formula", {{"formula", textValue(sum)}}, {}, "root"));
  EXPECT_DOUBLE_EQ(p.eval(0.5, 0, 0), 0.5);
}

TEST(BadModel, NaNConstantsStayNaN) {
  // folding kept NaN apart from other constants: sqrt(-1) + 1.5 is NaN, not 1.5
  const Program p = compile(makeNode(
      "formula", {{"formula", textValue("sqrt(-1) + 1.5 - sqrt(x*x+y*y+z*z)")}}, {}, "root"));
  EXPECT_TRUE(std::isnan(p.eval(0, 0, 0)));
  expectHas(messageOf([] {
              makeNode("formula",
                       {{"formula", textValue("r - x")}, {"parameters", textValue("r = 0/0")}}, {},
                       "root");
            }),
            "is not a finite number");
}

class TempDir : public ::testing::Test {
 protected:
  void SetUp() override {
    char pattern[] = "/tmp/frep-bad-XXXXXX";
    dir = mkdtemp(pattern);
  }
  void TearDown() override { fs::remove_all(dir); }
  std::string file(const std::string& name, const std::string& content) {
    const std::string path = dir + "/" + name;
    std::ofstream(path, std::ios::binary) << content;
    return path;
  }
  std::string dir;
};

using BadFiles = TempDir;

TEST_F(BadFiles, FoldersFifosAndHugeFilesAreNotRead) {
  fs::create_directory(dir + "/model.json");
  expectHas(messageOf([&] { loadModel(dir + "/model.json"); }), "is a folder");
  const std::string fifo = dir + "/pipe.json";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  expectHas(messageOf([&] { loadModel(fifo); }), "not a regular file");  // and no hang
  const std::string fifoStl = dir + "/pipe.stl";
  ASSERT_EQ(mkfifo(fifoStl.c_str(), 0600), 0);
  expectHas(messageOf([&] { readMesh(fifoStl); }), "not a regular file");
  expectHas(messageOf([] { loadModel("/dev/zero"); }), "not a regular file");
  const std::string big = dir + "/big.json";
  {
    std::ofstream out(big);
    out.seekp(static_cast<std::streamoff>(kMaxModelBytes) + 10);
    out << ' ';
  }
  expectHas(messageOf([&] { loadModel(big); }), "too large for a model file");
}

TEST_F(BadFiles, LyingAndGarbageMeshFiles) {
  // a binary STL whose header claims more triangles than the file holds
  std::string stl(84 + 50, '\0');
  const std::uint32_t claims = 1000000;
  std::memcpy(&stl[80], &claims, 4);
  expectHas(messageOf([&] { readMesh(file("lie.stl", stl)); }), "not an STL file");
  // garbage after 'solid' is bad input, not an empty (unprintable) mesh
  expectHas(messageOf([&] { readMesh(file("junk.stl", "solid x\nhello world\n")); }),
            "unexpected 'hello'");
  expectHas(messageOf([&] { readMesh(file("cut.stl", "solid x\nfacet normal 0 0 1\n")); }),
            "without 'endsolid'");
  // OBJ and PLY indices out of range, a PLY element without properties (looped forever)
  expectHas(messageOf([&] { readMesh(file("a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")); }),
            "vertex index 8 out of range (3 vertices)");
  expectHas(messageOf([&] {
              readMesh(file("a.ply",
                            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                            "property float y\nproperty float z\nelement face 1\n"
                            "property list uchar int vertex_indices\nend_header\n"
                            "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"));
            }),
            "out of range");
  expectHas(messageOf([&] {
              readMesh(file("b.ply",
                            "ply\nformat ascii 1.0\nelement junk 4000000000000\n"
                            "end_header\n"));
            }),
            "element 'junk' has no properties");
}

TEST_F(BadFiles, ReportsOfFilesWithNonUtf8NamesAreValidJson) {
  const CheckReport r;
  const std::string json = reportToJson(r, dir + "/caf\xe9.stl");
  EXPECT_NE(json.find("caf\\\\xE9.stl"), std::string::npos) << json;
}

}  // namespace
}  // namespace frep
