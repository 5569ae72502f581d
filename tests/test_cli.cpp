// The printlight command line: each bad input (a missing or unreadable file,
// a malformed scene, a bad option) gives a one-line error naming the file,
// a non-zero exit and no output file; good input writes EXR, PNG and VDB
// and a summary line; --threads does not change a single bit of the result.
// (Over 500 lines: one file for every command's end-to-end behaviour,
// sharing the TestScene fixture.)
#include <algorithm>
#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/rng.h"
#include "io/grid_io.h"
#include "io/image_io.h"
#include "io/mesh_io.h"
#include "test_util.h"

namespace pl {
namespace {

namespace fs = std::filesystem;

using test::CliRun;
using test::readText;

CliRun printlight(const std::string& args, const fs::path& dir) { return test::runPrintlight(args, dir); }

void writeText(const fs::path& p, const std::string& s) { std::ofstream(p) << s; }

// A small valid scene: 2 mm white cube, 0.1 mm voxels, surface-voxel sensor.
struct TestScene {
    fs::path dir;
    nlohmann::json scene;
    explicit TestScene(const std::string& name) : dir(test::freshTempDir("cli_" + name)) {
        writeObj(test::boxMesh({0, 0, 0}, {2, 2, 2}), dir / "cube.obj");
        writeLabelGridBin(test::boxGrid({20, 20, 20}, {0.1f, 0.1f, 0.1f}, [](const Vec3i&) { return Label(4); }),
                          dir / "grid.bin");
        fs::copy_file(test::sourceDir() / "data/materials/resins_illustrative.json", dir / "materials.json");
        scene = {{"object", {{"mesh", "cube.obj"}, {"labels", "grid.bin"}, {"materials", "materials.json"}, {"ior", 1.5}}},
                 {"sensor", {{"type", "surface_voxels"}}},
                 {"render", {{"spp", 2}, {"seed", 7}}}};
    }
    fs::path write() const {
        writeText(dir / "scene.json", scene.dump(2));
        return dir / "scene.json";
    }
    fs::path out() const { return dir / "out" / "result"; }
    CliRun render(const std::string& extra = "") const {
        return printlight("render " + write().string() + " -o " + out().string() + " " + extra, dir);
    }
    bool anyOutput() const {
        if (!fs::exists(out().parent_path())) return false;
        return !fs::is_empty(out().parent_path());  // not even a temporary file
    }
};

// The printer's characterisation for TestScene's voxels, small and quick
// (optimize would otherwise make the full one on first use).
std::string smallGamut(const TestScene& s) {
    const fs::path file = s.dir / "gamut.json";
    if (!fs::exists(file)) {
        const CliRun r = printlight("characterise " + (s.dir / "materials.json").string() +
                                        " --levels 2 --cube-mm 3 --voxel-mm 0.1,0.1,0.1 --spp 4 -o " + file.string(),
                                    s.dir);
        EXPECT_EQ(r.exitCode, 0) << r.err;
    }
    return " --gamut " + file.string();
}

void expectCleanFailure(const TestScene& s, const CliRun& r, const std::string& fileNeedle,
                        const std::string& problemNeedle) {
    EXPECT_EQ(r.exitCode, 1) << r.err;
    ASSERT_FALSE(r.err.empty());
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "not one line: " << r.err;
    EXPECT_EQ(r.err.rfind("printlight: error: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(fileNeedle), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(problemNeedle), std::string::npos) << r.err;
    EXPECT_FALSE(s.anyOutput()) << "output written despite the error";
    EXPECT_TRUE(r.out.empty()) << r.out;
}

TEST(Cli, GoodSceneWritesAllOutputsAndASummary) {
    TestScene s("good");
    CliRun r = s.render("--threads 2");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    for (const char* ext : {".exr", ".png", ".vdb", ".glb"}) EXPECT_TRUE(fs::exists(s.out().string() + ext)) << ext;
    EXPECT_NE(r.out.find("paths/s"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("scattering events/s"), std::string::npos) << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
    // Exactly the outputs: no stray temporary files.
    size_t files = 0;
    for (const auto& e : fs::directory_iterator(s.out().parent_path())) files += e.is_regular_file();
    EXPECT_EQ(files, 4u);
    RadianceImage im = readExr(s.out().string() + ".exr");
    double sum = 0, covered = 0;
    for (size_t i = 0; i < im.mean.size(); ++i) {
        sum += im.mean[i][0] * im.coverage[i];
        covered += im.coverage[i];
    }
    EXPECT_GT(covered, 0);
    EXPECT_GT(sum / covered, 0.05);  // a white cube is bright
}

TEST(Cli, SameSeedSameBitsWhateverTheThreadCount) {
    TestScene s("threads");
    ASSERT_EQ(s.render("--threads 1").exitCode, 0);
    RadianceImage a = readExr(s.out().string() + ".exr");
    fs::remove_all(s.out().parent_path());
    ASSERT_EQ(s.render("--threads 2").exitCode, 0);
    RadianceImage b = readExr(s.out().string() + ".exr");
    ASSERT_EQ(a.mean.size(), b.mean.size());
    for (size_t i = 0; i < a.mean.size(); ++i) {
        ASSERT_EQ(a.mean[i], b.mean[i]) << i;
        ASSERT_EQ(a.standardError[i], b.standardError[i]) << i;
    }
}

// A render with a target error or a time budget stops by it, in rounds
// whose N samples are the bits of --spp N (so the summary's spp
// reproduces it), and its median relative error is at the target.
TEST(Cli, RendersStopAtATargetErrorOrATimeAndReproduceWithTheirSpp) {
    TestScene s("progressive");
    CliRun r = s.render("--target-error 0.05");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const size_t at = r.out.find("stopped by target error at ");
    ASSERT_NE(at, std::string::npos) << r.out;
    const int spp = std::atoi(r.out.c_str() + at + std::strlen("stopped by target error at "));
    EXPECT_GT(spp, 2) << r.out;
    const RadianceImage a = readExr(s.out().string() + ".exr");
    EXPECT_EQ(a.meta("spp"), std::to_string(spp));
    std::vector<double> relative;
    for (size_t i = 0; i < a.mean.size(); ++i)
        if (a.coverage[i] > 0 && a.standardError[i][1] > 0) relative.push_back(a.standardError[i][1] / a.mean[i][1]);
    std::nth_element(relative.begin(), relative.begin() + long(relative.size() / 2), relative.end());
    EXPECT_LE(relative[relative.size() / 2], 0.05);

    fs::remove_all(s.out().parent_path());
    ASSERT_EQ(s.render("--spp " + std::to_string(spp)).exitCode, 0);
    const RadianceImage b = readExr(s.out().string() + ".exr");
    ASSERT_EQ(a.mean.size(), b.mean.size());
    for (size_t i = 0; i < a.mean.size(); ++i) {
        ASSERT_EQ(a.mean[i], b.mean[i]) << i;
        ASSERT_EQ(a.standardError[i], b.standardError[i]) << i;
    }

    r = s.render("--time 0.5");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("stopped by time at "), std::string::npos) << r.out;
    EXPECT_EQ(s.render("--time -1").exitCode, 2);
}

// A CSV file's rows after its header, as cells, or as numbers where every cell is one.
std::vector<std::vector<std::string>> readCsvCells(const fs::path& file) {
    std::vector<std::vector<std::string>> rows;
    std::istringstream in(test::readText(file));
    std::string line;
    std::getline(in, line);  // header
    while (std::getline(in, line)) {
        std::vector<std::string> row;
        std::istringstream cells(line);
        for (std::string cell; std::getline(cells, cell, ',');) row.push_back(cell);
        rows.push_back(row);
    }
    return rows;
}
std::vector<std::vector<double>> readCsvNumbers(const fs::path& file) {
    std::vector<std::vector<double>> rows;
    for (const auto& cells : readCsvCells(file)) {
        std::vector<double> row;
        for (const std::string& cell : cells) {
            // A text cell (optimize's predictor column) reads as NaN.
            double v = std::nan("");
            try {
                v = std::stod(cell);
            } catch (const std::invalid_argument&) {
            }
            row.push_back(v);
        }
        rows.push_back(row);
    }
    return rows;
}

// Across MPI ranks (when built with MPI and mpirun is there): the pixels
// are split, rank 0 gathers and writes, and the result has the bits of the
// one-process render: per pixel (volpath, printpt), with light paths
// shared round the ranks (lighttrace), and in progressive rounds whose
// size rank 0 decides (--target-error).
TEST(Cli, MpiRanksGiveTheBitsOfOneProcess) {
    TestScene s("mpi");
    if (printlight("--version", s.dir).out.find("with MPI") == std::string::npos || std::system("command -v mpirun >/dev/null") != 0)
        GTEST_SKIP() << "built without MPI or no mpirun";
    const std::string mpirun = std::string("mpirun -n 2 --oversubscribe") + (::getuid() == 0 ? " --allow-run-as-root" : "") +
                               " " + PRINTLIGHT_EXE + " render " + s.write().string() + " --threads 1 ";
    auto expectSameBits = [&](const std::string& options) {
        ASSERT_EQ(s.render(options).exitCode, 0) << options;
        const RadianceImage one = readExr(s.out().string() + ".exr");
        fs::remove_all(s.out().parent_path());
        const std::string command =
            mpirun + options + " -o " + s.out().string() + " >" + (s.dir / "mpi.log").string() + " 2>&1";
        ASSERT_EQ(std::system(command.c_str()), 0) << readText(s.dir / "mpi.log");
        EXPECT_NE(readText(s.dir / "mpi.log").find("2 MPI ranks"), std::string::npos) << readText(s.dir / "mpi.log");
        const RadianceImage two = readExr(s.out().string() + ".exr");
        ASSERT_EQ(one.mean.size(), two.mean.size());
        for (size_t i = 0; i < one.mean.size(); ++i) {
            ASSERT_EQ(one.mean[i], two.mean[i]) << options << " " << i;
            ASSERT_EQ(one.standardError[i], two.standardError[i]) << options << " " << i;
        }
        fs::remove_all(s.out().parent_path());
    };
    expectSameBits("--spp 4 --integrator volpath");
    expectSameBits("--spp 4 --integrator printpt");
    expectSameBits("--target-error 0.3 --integrator volpath");
    // batch: the jobs dealt round the ranks, the same results and one CSV.
    writeText(s.dir / "manifest.json", R"({"renders": [
        {"name": "a", "scene": "scene.json", "spp": 2, "seed": 5, "channel": "rgb"},
        {"name": "b", "scene": "scene.json", "spp": 2, "seed": 6, "channel": "g"},
        {"name": "c", "scene": "scene.json", "spp": 3, "seed": 7, "channel": "rgb"}]})");
    ASSERT_EQ(printlight("batch " + (s.dir / "manifest.json").string() + " -o " + (s.dir / "one").string(), s.dir).exitCode, 0);
    const std::string batch = std::string("mpirun -n 2 --oversubscribe") + (::getuid() == 0 ? " --allow-run-as-root" : "") +
                              " " + PRINTLIGHT_EXE + " batch " + (s.dir / "manifest.json").string() + " -o " +
                              (s.dir / "two").string() + " --compare " + (s.dir / "one").string() + " >" +
                              (s.dir / "batch.log").string() + " 2>&1";
    ASSERT_EQ(std::system(batch.c_str()), 0) << readText(s.dir / "batch.log");
    const std::string batchLog = readText(s.dir / "batch.log");
    EXPECT_NE(batchLog.find("all results agree"), std::string::npos) << batchLog;
    EXPECT_EQ(std::count(batchLog.begin(), batchLog.end(), '['), 3) << batchLog;  // each job reported once
    EXPECT_EQ(std::count(batchLog.begin(), batchLog.end(), '\n'), 7) << batchLog;
    const std::string csv = readText(s.dir / "two" / "batch.csv");
    EXPECT_LT(csv.find("\na,"), csv.find("\nb,"));
    EXPECT_LT(csv.find("\nb,"), csv.find("\nc,"));

    // optimize: every rank runs the loop on the same predictions, each
    // rendering its share of them (adaptive rounds too).
    const std::string launcher = std::string("mpirun --oversubscribe") + (::getuid() == 0 ? " --allow-run-as-root" : "");
    const std::string optimize = std::string(" optimize ") + s.write().string() + smallGamut(s) +
                                 " --target 0.2,0.45,0.8 --iterations 2 --spp 2 --threads 1 -o ";
    ASSERT_EQ(printlight(optimize + (s.dir / "one" / "opt").string(), s.dir).exitCode, 0);
    const std::string optimizeOnRanks = launcher + " -n 2 " + PRINTLIGHT_EXE + optimize + (s.dir / "two" / "opt").string() +
                                        " >" + (s.dir / "opt.log").string() + " 2>&1";
    ASSERT_EQ(std::system(optimizeOnRanks.c_str()), 0) << readText(s.dir / "opt.log");
    const auto oneRows = readCsvNumbers((s.dir / "one" / "opt.csv").string());
    const auto twoRows = readCsvNumbers((s.dir / "two" / "opt.csv").string());
    ASSERT_EQ(oneRows.size(), twoRows.size());
    for (size_t i = 0; i < oneRows.size(); ++i)
        for (size_t column : {1, 2, 3, 4, 6}) EXPECT_EQ(oneRows[i][column], twoRows[i][column]) << i << " " << column;
    EXPECT_EQ(loadLabelGrid(s.dir / "one" / "opt_labels.vdb", std::nullopt).histogram(),
              loadLabelGrid(s.dir / "two" / "opt_labels.vdb", std::nullopt).histogram());
    EXPECT_EQ(test::countOf(readText(s.dir / "opt.log"), "iteration,"), 1) << "rank 0 speaks";

    // A failure on one rank (its memory budget too small to load the
    // grid): every rank stops, rank 0 prints one line naming the rank, and
    // nothing is written (mpirun adds its own notice).
    const std::string oneRankFails = launcher + " -n 1 " + PRINTLIGHT_EXE + " render " + s.write().string() +
                                     " --spp 1 -o " + s.out().string() + " : -n 1 env PRINTLIGHT_MEMORY_LIMIT_MB=1 " +
                                     PRINTLIGHT_EXE + " render " + s.write().string() + " --spp 1 -o " +
                                     s.out().string() + " >" + (s.dir / "fail.log").string() + " 2>&1";
    EXPECT_NE(std::system(oneRankFails.c_str()), 0);
    const std::string failLog = readText(s.dir / "fail.log");
    EXPECT_EQ(test::countOf(failLog, "printlight: error"), 1) << failLog;
    EXPECT_NE(failLog.find("printlight: error: MPI rank 1: "), std::string::npos) << failLog;
    EXPECT_NE(failLog.find("refused before allocating"), std::string::npos) << failLog;
    EXPECT_FALSE(s.anyOutput());

    // A failure on the ranks: one line, from rank 0, and no output.
    const std::string failing = mpirun + "--integrator lighttrace -o " + s.out().string() + " >" +
                                (s.dir / "mpi.log").string() + " 2>&1";
    EXPECT_NE(std::system(failing.c_str()), 0);
    const std::string log = readText(s.dir / "mpi.log");
    EXPECT_NE(log.find("lighttrace scores into surface-voxel patches"), std::string::npos) << log;
    EXPECT_EQ(log.find("lighttrace scores"), log.rfind("lighttrace scores")) << "one error line, from rank 0: " << log;
    EXPECT_FALSE(s.anyOutput());

    // lighttrace's films hold each rank's share alone, pooled across the
    // ranks (keys and windows) and gathered settled: a one-resin cube is
    // printpt's camera side on every pixel (windows over both ranks'
    // pixels), then the light side on every pixel.
    s.scene["sensor"]["footprint"] = "patch";
    s.write();
    expectSameBits("--spp 3 --integrator lighttrace");
    // One channel: the others are settled empty on every rank alike.
    expectSameBits("--spp 2 --integrator lighttrace --channel g");
    s.scene["render"]["integrator"] = "lighttrace";  // a scene holds its estimator's keys alone
    s.scene["render"]["lighttrace_hybrid"] = false;
    s.write();
    expectSameBits("--spp 3");
}

TEST(Cli, CtrlCStopsPromptlyWritesNothingAndExits130) {
    TestScene s("interrupt");
    s.scene["render"]["spp"] = 1000000;  // hours of work
    const std::filesystem::path err = s.dir / "stderr.txt";
    const std::string render = std::string(PRINTLIGHT_EXE) + " render " + s.write().string() + " -o " +
                               s.out().string() + " >" + (s.dir / "stdout.txt").string() + " 2>" + err.string();
    // The signal comes once the render has started (its first line: the
    // scene is loaded), however slow the start on a busy machine.
    const std::string started = "for i in $(seq 1200); do [ -s " + err.string() + " ] && break; sleep 0.05; done";
    int status = std::system(("bash -c '" + render + " & p=$!; " + started + "; date +%s.%N > " +
                              (s.dir / "signalled.txt").string() + "; kill -INT $p; wait $p'")
                                 .c_str());
    const double seconds =
        std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count() -
        std::stod(test::readText(s.dir / "signalled.txt"));
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 130) << test::readText(err);
    EXPECT_LT(seconds, 10.0) << "the render did not stop promptly";
    EXPECT_NE(test::readText(err).find("interrupted"), std::string::npos);
    EXPECT_FALSE(s.anyOutput());
}

// One request delivered twice at once (timeout(1) signals the process and
// then its group; here three times) still stops cleanly, with the message.
TEST(Cli, OneInterruptDeliveredTwiceStillStopsCleanly) {
    TestScene s("interrupt_twice");
    s.scene["render"]["spp"] = 1000000;
    const std::filesystem::path err = s.dir / "stderr.txt";
    const std::string render = std::string(PRINTLIGHT_EXE) + " render " + s.write().string() + " -o " +
                               s.out().string() + " >/dev/null 2>" + err.string();
    // Once the render has started (its first line), as above.
    const std::string started = "for i in $(seq 1200); do [ -s " + err.string() + " ] && break; sleep 0.05; done";
    int status = std::system(
        ("bash -c '" + render + " & p=$!; " + started + "; kill -INT $p; kill -INT $p; kill -INT $p; wait $p'").c_str());
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 130);
    EXPECT_NE(test::readText(s.dir / "stderr.txt").find("interrupted"), std::string::npos)
        << test::readText(s.dir / "stderr.txt");
    EXPECT_FALSE(s.anyOutput());
}

TEST(Cli, MalformedSceneJson) {
    TestScene s("malformed");
    s.write();
    writeText(s.dir / "scene.json", "{ \"object\": { \"mesh\": ");
    CliRun r = printlight("render " + (s.dir / "scene.json").string() + " -o " + s.out().string(), s.dir);
    expectCleanFailure(s, r, "scene.json", "malformed JSON");
    // A number beyond double's range (found by fuzzing: nlohmann throws out_of_range).
    writeText(s.dir / "scene.json", "{ \"object\": 9e999 }");
    r = printlight("render " + (s.dir / "scene.json").string() + " -o " + s.out().string(), s.dir);
    expectCleanFailure(s, r, "scene.json", "malformed JSON");
}

TEST(Cli, MissingFiles) {
    TestScene s("missing");
    s.scene["object"]["mesh"] = "nowhere.obj";
    expectCleanFailure(s, s.render(), "nowhere.obj", "cannot open");
    CliRun r = printlight("render " + (s.dir / "no_scene.json").string(), s.dir);
    expectCleanFailure(s, r, "no_scene.json", "cannot open");
}

TEST(Cli, GridWithoutLabels) {
    TestScene s("nolabels");
    // A VDB that holds a grid, but not one named "labels".
    LabelGrid g = test::boxGrid({4, 4, 4}, {0.5f, 0.5f, 0.5f}, [](const Vec3i&) { return Label(4); });
    writeLabelGridVdb(g, s.dir / "grid.vdb");
    std::string bytes = readText(s.dir / "grid.vdb");
    // Rename the grid in place: same length, different name.
    auto pos = bytes.find("labels");
    ASSERT_NE(pos, std::string::npos);
    bytes.replace(pos, 6, "colors");
    std::ofstream(s.dir / "grid.vdb", std::ios::binary) << bytes;
    s.scene["object"]["labels"] = "grid.vdb";
    expectCleanFailure(s, s.render(), "grid.vdb", "no grid named 'labels'");
}

TEST(Cli, LabelsMissingFromTheMaterialTable) {
    TestScene s("missinglabel");
    writeLabelGridBin(test::boxGrid({20, 20, 20}, {0.1f, 0.1f, 0.1f}, [](const Vec3i& v) { return Label(v.x < 10 ? 4 : 9); }),
                      s.dir / "grid.bin");
    expectCleanFailure(s, s.render(), "grid.bin", "label 9");
}

TEST(Cli, BadCoefficients) {
    struct Case {
        std::string materials, problem;
    };
    const std::vector<Case> cases = {
        {R"([{"label":4,"albedo":[1,1,1],"density":[6,-9,24]}])", "must not be negative"},
        {R"([{"label":4,"albedo":[1,1,1],"density":[6,NaN,24]}])", "malformed JSON"},
        {R"([{"label":4,"albedo":[1,1,1],"density":[6,9,24],"anisotropy":[0.4,1.0,0.4]}])", "|g| < 1"},
        {R"([{"label":4,"albedo":[1,1,1],"density":[6,9,24],"anisotropy":-1.5}])", "|g| < 1"},
    };
    for (size_t i = 0; i < cases.size(); ++i) {
        TestScene s("coeff" + std::to_string(i));
        writeText(s.dir / "materials.json", cases[i].materials);
        expectCleanFailure(s, s.render(), "materials.json", cases[i].problem);
    }
}

TEST(Cli, NonPositiveIor) {
    for (double ior : {0.0, -1.5}) {
        TestScene s("ior");
        s.scene["object"]["ior"] = ior;
        expectCleanFailure(s, s.render(), "scene.json", "object.ior");
    }
}

TEST(Cli, NegativeHomogeneousCoreDepth) {
    TestScene s("core_depth");
    s.scene["object"]["homogeneous_core_depth_mm"] = -0.5;
    expectCleanFailure(s, s.render(), "scene.json", "object.homogeneous_core_depth_mm");
}

TEST(Cli, NonClosedMesh) {
    TestScene s("open");
    TriangleMesh m = test::boxMesh({0, 0, 0}, {2, 2, 2});
    m.indices.resize(m.indices.size() - 6);  // drop one face
    writeObj(m, s.dir / "cube.obj");
    expectCleanFailure(s, s.render(), "cube.obj", "not closed");
}

TEST(Cli, MeshThatDoesNotOverlapTheGrid) {
    TestScene s("nooverlap");
    writeObj(test::boxMesh({50, 50, 50}, {52, 52, 52}), s.dir / "cube.obj");
    expectCleanFailure(s, s.render(), "cube.obj", "does not overlap");
}

TEST(Cli, AbsurdResolutions) {
    TestScene s("absurd");
    s.scene["sensor"] = {{"type", "perspective"}, {"position", {5, 5, 5}}, {"look_at", {1, 1, 1}},
                         {"resolution", {100000, 20}}};
    expectCleanFailure(s, s.render(), "scene.json", "sensor.resolution");
    s.scene["sensor"]["resolution"] = {0, 10};
    expectCleanFailure(s, s.render(), "scene.json", "sensor.resolution");
    // A grid file whose header claims 2^60 voxels.
    TestScene g("absurdgrid");
    std::string bytes = readText(g.dir / "grid.bin");
    int32_t huge[3] = {1 << 20, 1 << 20, 1 << 20};
    bytes.replace(0, 12, reinterpret_cast<const char*>(huge), 12);
    std::ofstream(g.dir / "grid.bin", std::ios::binary) << bytes;
    expectCleanFailure(g, g.render(), "grid.bin", "too large");
}

// Jobs that cannot fit are refused before the big allocations, with the
// estimate in the one-line error (the budget is lowered through the
// environment so the test does not depend on the machine's memory).
TEST(Cli, RefusesJobsThatDoNotFitInMemory) {
    TestScene s("memory");
    ::setenv("PRINTLIGHT_MEMORY_LIMIT_MB", "1", 1);
    CliRun r = printlight("render " + (test::sourceDir() / "data/scenes/cube10_greek_surface.json").string() + " -o " +
                              s.out().string(), s.dir);
    ::unsetenv("PRINTLIGHT_MEMORY_LIMIT_MB");
    expectCleanFailure(s, r, "cube10_greek.vdb", "of memory; this machine has 1.0 MiB (refused before allocating)");
    // The scene fits in 200 MiB (about 160 in use), its surface sensor, film and images (~86 MiB) on top do
    // not: refused before they are made, with what would fit.
    ::setenv("PRINTLIGHT_MEMORY_LIMIT_MB", "200", 1);
    r = printlight("render " + (test::sourceDir() / "data/scenes/cube10_greek_surface.json").string() + " -o " +
                   s.out().string(), s.dir);
    ::unsetenv("PRINTLIGHT_MEMORY_LIMIT_MB");
    expectCleanFailure(s, r, "cube10_greek_surface.json", "318634 surface voxels needs about");
    EXPECT_NE(r.err.find("the ray footprint with volpath or printpt needs"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("prepare --voxel"), std::string::npos) << r.err;
    // prepare: a 0.02 mm grid of the 10 mm cube (~1.4e8 voxels) against 64 MiB.
    ::setenv("PRINTLIGHT_MEMORY_LIMIT_MB", "64", 1);
    r = printlight("prepare " + (test::sourceDir() / "data/models/cube10.gltf").string() + " -o " +
                       (s.out().string() + ".vdb") + " --voxel 0.02,0.02,0.02", s.dir);
    ::unsetenv("PRINTLIGHT_MEMORY_LIMIT_MB");
    expectCleanFailure(s, r, "cube10.gltf", "needs about");
    // Far beyond any machine: refused as too large, and quickly.
    r = printlight("prepare " + (test::sourceDir() / "data/models/cube10.gltf").string() + " -o " +
                       (s.out().string() + ".vdb") + " --voxel 0.0001,0.0001,0.0001", s.dir);
    expectCleanFailure(s, r, "cube10.gltf", "too large");
}

// The photon estimators store a point or a beam per collision or flight,
// about 50 per photon in white resin: an iteration that outgrows the memory
// stops with an error that says so (after the summary line), and writes nothing.
TEST(Cli, PhotonEstimatorsStopWhenTheirPhotonsOutgrowTheMemory) {
    for (const char* estimator : {"bre", "pp3d", "pb2d", "bb1d", "combined"}) {
        TestScene s(std::string("photons_") + estimator);
        // About 250 MiB in use once the scene is loaded: room for ~1e6 photons'
        // items, which white's red channel outgrows within a few per cent of its photons.
        ::setenv("PRINTLIGHT_MEMORY_LIMIT_MB", "350", 1);
        const CliRun r = printlight("render " + (test::sourceDir() / "data/scenes/cube10_white_preview.json").string() +
                                        " --spp 1 --integrator " + estimator + " -o " + s.out().string(),
                                    s.dir);
        ::unsetenv("PRINTLIGHT_MEMORY_LIMIT_MB");
        EXPECT_EQ(r.exitCode, 1) << r.err;
        EXPECT_NE(r.err.find("printlight: error: one iteration's photons outgrow the memory ("), std::string::npos)
            << r.err;
        const std::string name = estimator;
        const bool ownCount = name == "bre" || name == "pp3d" || name == "combined";
        const std::string remedy = ownCount ? "lower " + name + "_photons_per_pixel" : "lower beams_photons_per_pixel";
        EXPECT_NE(r.err.find(remedy), std::string::npos)
            << r.err;
        EXPECT_FALSE(s.anyOutput()) << "output written despite the error";
    }
}

// The render block's keys beyond its own are the estimator's: a key it
// does not read is refused with the list of those it does, another
// estimator's too.
TEST(Cli, UnknownSceneKeysAreTypos) {
    TestScene s("typo");
    s.scene["render"]["integrator"] = "volpath";
    s.scene["render"]["sps"] = 4;
    CliRun r = s.render();
    expectCleanFailure(s, r, "scene.json", "render.sps");
    EXPECT_NE(r.err.find("not an option of volpath (its options: max_depth, clearance_first)"), std::string::npos)
        << r.err;
    TestScene other("another_estimators_key");
    other.scene["render"]["integrator"] = "volpath";
    other.scene["render"]["branches"] = 2;
    expectCleanFailure(other, other.render(), "scene.json", "render.branches");
}

TEST(Cli, MajorantsAreBricksAGlobalOneOrDecomposition) {
    TestScene unknown("majorants_unknown");
    unknown.scene["render"]["majorants"] = "leaf";
    CliRun r = unknown.render();
    expectCleanFailure(unknown, r, "scene.json", "render.majorants");
    EXPECT_NE(r.err.find("must be bricks, global or decomposition"), std::string::npos) << r.err;
    // Decomposition tracking follows one channel a flight.
    TestScene hero("decomposition_hero");
    hero.scene["render"]["majorants"] = "decomposition";
    hero.scene["render"]["channel_sampling"] = "hero";
    r = hero.render();
    expectCleanFailure(hero, r, "scene.json", "render.majorants");
    EXPECT_NE(r.err.find("decomposition tracks one channel a flight"), std::string::npos) << r.err;
}

// An estimator declares the sensors it takes: the scene is refused before
// anything loads.
TEST(Cli, EstimatorsRefuseSensorsTheyDoNotTake) {
    TestScene s("lighttrace_ray_footprint");
    s.scene["render"]["integrator"] = "lighttrace";
    CliRun r = s.render();
    expectCleanFailure(s, r, "scene.json: 'sensor'", "lighttrace takes a \"surface_voxels\" sensor with "
                                                     "\"footprint\": \"patch\" only");
}

// printpt's switches: one table for the scene file and bench's overrides.
TEST(Cli, PrintPtSwitchesAreChecked) {
    struct Case {
        const char* key;
        nlohmann::json value;
        const char* problem;
    } cases[] = {{"rr_threshold", 0.0, "must be in (0, 1]"},
                 {"branches", 0, "1..1024"},
                 {"ball_min_mfp", -1.0, ">= 0"},
                 {"ball_walks", 3, "must be"},
                 {"control_mean_walks_per_entry", -1, "0..1e9"}};
    for (const Case& c : cases) {
        TestScene s(std::string("switch_") + c.key);
        s.scene["render"]["integrator"] = "printpt";
        s.scene["render"][c.key] = c.value;
        CliRun r = s.render();
        expectCleanFailure(s, r, "scene.json", std::string("render.") + c.key);
        EXPECT_NE(r.err.find(c.problem), std::string::npos) << r.err;
    }
}

TEST(Cli, NeverOverwritesAnInput) {
    TestScene s("overwrite");
    writeLabelGridVdb(test::boxGrid({20, 20, 20}, {0.1f, 0.1f, 0.1f}, [](const Vec3i&) { return Label(4); }),
                      s.dir / "labels.vdb");
    s.scene["object"]["labels"] = "labels.vdb";
    std::string before = readText(s.dir / "labels.vdb");
    // -o DIR/labels would write DIR/labels.vdb: the input grid.
    CliRun r = printlight("render " + s.write().string() + " -o " + (s.dir / "labels").string(), s.dir);
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("overwrite an input"), std::string::npos) << r.err;
    EXPECT_EQ(readText(s.dir / "labels.vdb"), before);
    EXPECT_FALSE(fs::exists(s.dir / "labels.exr"));
}

TEST(Cli, UsageErrorsExitWithTwo) {
    TestScene s("usage");
    EXPECT_EQ(printlight("render", s.dir).exitCode, 2);
    EXPECT_EQ(printlight("render " + s.write().string() + " --spp zero", s.dir).exitCode, 2);
    EXPECT_EQ(printlight("frobnicate", s.dir).exitCode, 2);
    EXPECT_FALSE(s.anyOutput());
}

// A usage error is one line that names the option and points at the
// command's help; --help lists every option with what it does.
TEST(Cli, UsageErrorsAreOneLineAndHelpListsTheOptions) {
    TestScene s("usage_line");
    CliRun bad = printlight("render " + s.write().string() + " --sppp 4", s.dir);
    EXPECT_EQ(bad.exitCode, 2);
    EXPECT_NE(bad.err.find("--sppp"), std::string::npos) << bad.err;
    EXPECT_NE(bad.err.find("printlight render --help"), std::string::npos) << bad.err;
    EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
    EXPECT_FALSE(s.anyOutput());

    for (const char* command : {"render", "prepare", "optimize", "predict", "bench", "batch", "stability", "info"}) {
        CliRun help = printlight(std::string(command) + " --help", s.dir);
        EXPECT_EQ(help.exitCode, 0) << command << help.err;
        EXPECT_NE(help.out.find(std::string("printlight ") + command), std::string::npos) << help.out;
        if (std::string(command) != "info") {
            EXPECT_NE(help.out.find("--threads"), std::string::npos) << command << help.out;
        }
    }
    CliRun renderHelp = printlight("render --help", s.dir);
    EXPECT_NE(renderHelp.out.find("--spp N"), std::string::npos) << renderHelp.out;
    EXPECT_NE(renderHelp.out.find("samples per pixel"), std::string::npos) << renderHelp.out;

    CliRun list = printlight("--help", s.dir);
    EXPECT_EQ(list.exitCode, 0);
    for (const char* command : {"render", "prepare", "optimize", "bench"})
        EXPECT_NE(list.out.find(std::string("  ") + command + " "), std::string::npos) << list.out;
}

// --version names the version and the code fingerprint batch records.
TEST(Cli, VersionNamesTheCodeFingerprint) {
    TestScene s("version");
    CliRun r = printlight("--version", s.dir);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.out.rfind("printlight ", 0), 0u) << r.out;
    EXPECT_NE(r.out.find("(code "), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("unknown"), std::string::npos) << r.out;
}

// glTF coordinates are metres (its specification): prepare reads them so,
// says the model's size and unit, warns when the size looks like the wrong
// unit, scales to a print size with --fit-mm, and the scenes it writes
// place the mesh the same way (the render finds mesh and grid together).
TEST(Cli, PrepareReadsGltfInMetresAndFitsToASize) {
    TestScene s("units");
    writeGltf(test::boxMesh({0, 0, 0}, {2, 2, 2}), SurfaceAppearance{}, "", s.dir / "box.gltf");
    const std::string prepare = "prepare " + (s.dir / "box.gltf").string() + " --voxel 0.1,0.1,0.1 ";
    CliRun r = printlight(prepare + "-o " + (s.dir / "box.vdb").string(), s.dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("2 x 2 x 2 mm (coordinates in m: glTF coordinates are metres)"), std::string::npos) << r.out;
    EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;

    r = printlight(prepare + "--units mm -o " + (s.dir / "tiny.vdb").string(), s.dir);
    EXPECT_NE(r.err.find("warning: the model is 0.002 mm across: is its unit right?"), std::string::npos) << r.err;

    r = printlight(prepare + "--units ft -o " + (s.dir / "ft.vdb").string(), s.dir);
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.err.find("--units must be m, mm or in"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(s.dir / "ft.vdb"));

    // With the material table, the mixtures come from the printer's gamut.
    r = printlight(prepare + "--mixing gamut -o " + (s.dir / "nogamut.vdb").string(), s.dir);
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.err.find("--mixing gamut needs --materials"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(s.dir / "nogamut.vdb"));
    r = printlight(prepare + "--intent perceptual -o " + (s.dir / "nogamut.vdb").string(), s.dir);
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.err.find("--intent goes with --mixing gamut"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(s.dir / "nogamut.vdb"));
    r = printlight(prepare + "--fit-mm 4 --intent perceptual --materials " + (s.dir / "materials.json").string() +
                       smallGamut(s) +
                       " --scene-out " + (s.dir / "fit").string() + " -o " + (s.dir / "fit.vdb").string(),
                   s.dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("mixtures:  the printer's gamut: " + (s.dir / "gamut.json").string()), std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find(", perceptual intent\n"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("4 x 4 x 4 mm (coordinates in m: glTF coordinates are metres; --fit-mm: scaled by 2)"),
              std::string::npos)
        << r.out;
    const nlohmann::json scene = nlohmann::json::parse(readText(s.dir / "fit_surface.json"));
    EXPECT_EQ(scene["object"]["mesh_units"], "m");
    EXPECT_NEAR(scene["object"]["mesh_scale"].get<double>(), 2.0, 1e-6);
    r = printlight("render " + (s.dir / "fit_surface.json").string() + " --spp 1 -o " + (s.dir / "fit_render").string(),
                   s.dir);
    EXPECT_EQ(r.exitCode, 0) << r.err;

    // Without --materials, the scenes get the bundled table and its
    // characterisation beside them, and the bundled scenes' settings.
    r = printlight(prepare.substr(0, prepare.find(" --voxel")) + " --fit-mm 1 --scene-out " + (s.dir / "own").string() +
                       " -o " + (s.dir / "own.vdb").string(),
                   s.dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("materials: the bundled table"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("mixtures:  the printer's gamut: " + (s.dir / "own_materials.gamut.json").string()),
              std::string::npos)
        << r.out;
    const nlohmann::json own = nlohmann::json::parse(readText(s.dir / "own_surface.json"));
    EXPECT_EQ(own["object"]["materials"], "own_materials.json");
    EXPECT_EQ(own["render"]["integrator"], "lighttrace");
    EXPECT_EQ(own["sensor"]["footprint"], "patch");
    // A box is convex: its preview needs no re-entry, and printpt serves it.
    const nlohmann::json preview = nlohmann::json::parse(readText(s.dir / "own_preview.json"));
    EXPECT_EQ(preview["render"]["integrator"], "printpt");
    EXPECT_FALSE(preview["render"].contains("reentry"));  // false, the default
    EXPECT_NE(r.out.find("own_preview.json (printpt: the mesh is convex, nothing re-enters)"), std::string::npos)
        << r.out;
    r = printlight("render " + (s.dir / "own_surface.json").string() + " --spp 1 -o " + (s.dir / "own_render").string(),
                   s.dir);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    // A prepare that fails leaves neither the grid nor the table behind.
    r = printlight("prepare " + (s.dir / "nothing.gltf").string() + " --scene-out " + (s.dir / "gone").string() +
                       " -o " + (s.dir / "gone.vdb").string(),
                   s.dir);
    EXPECT_NE(r.exitCode, 0);
    EXPECT_FALSE(fs::exists(s.dir / "gone_materials.json"));
    EXPECT_FALSE(fs::exists(s.dir / "gone.vdb"));

    // The scene key: a unit that does not exist is named.
    s.scene["object"]["mesh_units"] = "ft";
    expectCleanFailure(s, s.render(), "scene.json", "object.mesh_units");
}

// A report page in Debian's headless Chromium, driven by Playwright's core
// (web/show_page.mjs): waits until every view shows its model, then takes
// a screenshot. The seconds from the start of the page's load to its last
// view ready, or a negative number if it failed (its log in dir).
constexpr const char* kChromium = "/usr/bin/chromium";
double showPage(const fs::path& dir, const fs::path& html, const fs::path& shot) {
    const fs::path out = dir / "show_page.json", log = dir / "show_page.log";
    const std::string command = "node " + (fs::path(PRINTLIGHT_SOURCE_DIR) / "web" / "show_page.mjs").string() + " " +
                                kChromium + " " + html.string() + " " + shot.string() + " >" + out.string() + " 2>" +
                                log.string();
    if (std::system(command.c_str()) != 0) return -1;
    return nlohmann::json::parse(readText(out))["seconds"].get<double>();
}

// The prediction on the model: render writes OUT.glb (the mesh with its
// voxels' radiance baked into a texture, unlit), report makes a self-contained page
// of it, and headless Chromium (Debian's, which setup installs) shows the
// model: a screenshot whose view holds the cube in the colour predicted.
TEST(Cli, ReportShowsThePredictionOnTheModelInChromium) {
    if (!fs::exists(kChromium)) GTEST_SKIP() << "no " << kChromium << " (scripts/setup.sh installs it)";
    TestScene s("report");
    CliRun r = s.render("--spp 4");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const fs::path glb = s.out().string() + ".glb", html = s.dir / "report.html", shot = s.dir / "shot.png";
    ASSERT_TRUE(fs::exists(glb));
    const RadianceImage image = readExr(s.out().string() + ".exr");
    r = printlight("report " + glb.string() + " --labels prediction --title cube -o " + html.string(), s.dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(readText(html).find("http"), readText(html).find("http://www.w3.org"))
        << "the page must not fetch anything";

    ASSERT_GE(showPage(s.dir, html, shot), 0) << readText(s.dir / "show_page.log");
    const Texture screenshot = readTexture(shot);
    // The view is a 360 px canvas with a grey background (0.5 sRGB, 0.214
    // linear); inside the grey's bounding box, what is not grey is the
    // model, and it shows about the mean radiance the render predicted
    // (unlit; the cube is white resin: about equal channels).
    double predicted = 0, covered = 0;
    for (size_t i = 0; i < image.mean.size(); ++i)
        if (image.coverage[i] > 0) {
            predicted += image.mean[i][0];
            covered += 1;
        }
    predicted /= covered;
    auto at = [&](int x, int y) { return screenshot.linear[size_t(y) * size_t(screenshot.width) + size_t(x)]; };
    auto grey = [](const RGB& c) {
        return std::abs(c[0] - 0.214f) < 0.02f && std::abs(c[1] - 0.214f) < 0.02f && std::abs(c[2] - 0.214f) < 0.02f;
    };
    int x0 = screenshot.width, x1 = -1, y0 = screenshot.height, y1 = -1;
    for (int y = 0; y < screenshot.height; ++y)
        for (int x = 0; x < screenshot.width; ++x)
            if (grey(at(x, y))) {
                x0 = std::min(x0, x), x1 = std::max(x1, x);
                y0 = std::min(y0, y), y1 = std::max(y1, y);
            }
    ASSERT_GT(x1 - x0, 300) << "no view in the screenshot";
    ASSERT_GT(y1 - y0, 300) << "no view in the screenshot";
    int model = 0;
    double red = 0, green = 0;
    for (int y = y0 + 2; y < y1 - 1; ++y)
        for (int x = x0 + 2; x < x1 - 1; ++x)
            if (!grey(at(x, y))) {
                model += 1;
                red += at(x, y)[0];
                green += at(x, y)[1];
            }
    ASSERT_GT(model, (x1 - x0) * (y1 - y0) / 10) << "the model is not in the view";
    EXPECT_NEAR(red / model, std::min(predicted, 1.0), 0.1) << "predicted " << predicted << ", " << model << " px";
    EXPECT_NEAR(green / model, red / model, 0.1);
}

// A 20 mm model's page, optimize's four views of it, shows every view in
// headless Chromium within 5 s of the start of its load: the
// prediction of a 20 mm cube at the printer's voxel (1.3 million surface
// voxels, each its own colour, a halftone's grain) written as optimize
// writes it.
TEST(CliAlone, ReportOfA20mmModelShowsInChromiumWithin5s) {
    if (!fs::exists(kChromium)) GTEST_SKIP() << "no " << kChromium << " (scripts/setup.sh installs it)";
    const fs::path dir = test::freshTempDir("report20");
    GridFrame frame;
    frame.voxelSize_mm = kPrinterVoxel_mm;
    // PRINTLIGHT_REPORT_SIDE_MM measures another size (docs/performance.md).
    const char* side = std::getenv("PRINTLIGHT_REPORT_SIDE_MM");
    const float side_mm = side ? std::stof(side) : 20.0f;
    for (int a = 0; a < 3; ++a) frame.resolution[a] = int(std::floor(side_mm / frame.voxelSize_mm[a]));
    const Point3f hi = frame.cornerMax_mm();
    std::vector<Vec3i> voxels;
    const Vec3i& n = frame.resolution;
    for (int z = 0; z < n.z; ++z)
        for (int y = 0; y < n.y; ++y)
            for (int x = 0; x < n.x; ++x)
                if (x == 0 || y == 0 || z == 0 || x == n.x - 1 || y == n.y - 1 || z == n.z - 1) voxels.push_back({x, y, z});
                else if (z > 0 && z < n.z - 1 && y > 0 && y < n.y - 1) x = n.x - 2;  // to the far face
    ASSERT_GT(voxels.size(), 1000000u);
    std::vector<RGB> colours(voxels.size());
    Rng rng(1, 0);
    for (RGB& c : colours)
        for (float& x : c) x = 0.3f + 0.4f * rng.uniform();
    const fs::path glb = dir / "p.glb", html = dir / "report.html";
    const auto t1 = std::chrono::steady_clock::now();
    writePredictionGlb(test::boxMesh({0, 0, 0}, hi), frame, voxels, colours, glb);
    const double glb_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
    const std::string g = glb.string();
    CliRun r = printlight("report " + g + " " + g + " " + g + " " + g + " --labels target,mapped,prediction,error -o " +
                              html.string(),
                          dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const double page_s = showPage(dir, html, dir / "shot.png");
    ASSERT_GE(page_s, 0) << readText(dir / "show_page.log");
    std::printf("%g mm model, %zu surface voxels: .glb %.1f MB written in %.1f s; 4 views: page %.1f MB, every view "
                "shown %.2f s after the load began\n",
                side_mm, voxels.size(), double(fs::file_size(glb)) / 1e6, glb_s, double(fs::file_size(html)) / 1e6,
                page_s);
    EXPECT_LT(page_s, 5.0);
    // The views hold the model, not only their grey.
    const Texture shot = readTexture(dir / "shot.png");
    size_t model = 0;
    for (const RGB& c : shot.linear)
        if (std::abs(c[0] - 0.214f) > 0.03f && c[0] > 0.05f && c[0] < 0.85f) ++model;
    EXPECT_GT(model, shot.linear.size() / 20);
    fs::remove_all(dir);
}

TEST(Cli, BenchWritesErrorTablesAgainstAReference) {
    TestScene s("bench");
    fs::path scene = s.write();
    fs::path ref = s.dir / "ref.exr";
    CliRun r = printlight("bench " + scene.string() + " --make-reference " + ref.string() + " --spp 32", s.dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("RMS standard error"), std::string::npos) << r.out;
    r = printlight("bench " + scene.string() + " --reference " + ref.string() +
                       " --budgets 0.05,0.1 --configs volpath,printpt --out " + (s.dir / "b").string(),
                   s.dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    std::string csv = readText(s.dir / "b.csv");
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 5) << csv;  // header + 2 configs x 2 budgets
    EXPECT_NE(csv.find("volpath,0.05,"), std::string::npos) << csv;
    EXPECT_NE(csv.find(",1.00,"), std::string::npos) << csv;  // volpath against itself
    EXPECT_TRUE(fs::exists(s.dir / "b.md"));
    EXPECT_NE(readText(s.dir / "b.svg").find("<polyline"), std::string::npos);
    // A reference of another scene is refused (a top-down view: the
    // default up, +y along z, is valid for it).
    s.scene["sensor"] = {{"type", "orthographic"}, {"position", {1, 1, 5}}, {"look_at", {1, 1, 0}},
                         {"width_mm", 1.0}, {"resolution", {8, 8}}};
    r = printlight("bench " + s.write().string() + " --reference " + ref.string(), s.dir);
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("does not match"), std::string::npos) << r.err;
}

// The whole-object column: the time to bring the median per-pixel relative
// error to the target, extrapolated as 1 / sqrt(time) from the render's.
TEST(Cli, BenchGivesTheTimeToATargetRelativeError) {
    TestScene s("bench_target");
    fs::path scene = s.write();
    CliRun r = printlight("bench " + scene.string() + " --self-variance --spp 4 --configs printpt --target-relative-error 0.001 --out " +
                              (s.dir / "t").string(),
                          s.dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const std::string csv = readText(s.dir / "t.csv");
    EXPECT_NE(csv.find(",median_rel_error,seconds_to_target,events_per_s_per_core,fraction_of_limit\n"),
              std::string::npos)
        << csv;
    std::vector<std::string> cells;
    std::istringstream row(csv.substr(csv.find('\n') + 1));
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
    ASSERT_EQ(cells.size(), 15u) << csv;
    // The event rate against the limit walk of the same run: a render does
    // lookups and boundary tests the limit walk does not.
    const double eventsPerCore = std::stod(cells[13]), ofLimit = std::stod(cells[14]);
    EXPECT_GT(eventsPerCore, 0.0) << csv;
    EXPECT_GT(ofLimit, 0.0) << csv;
    EXPECT_LT(ofLimit, 1.0) << csv;
    EXPECT_NE(readText(s.dir / "t.md").find("Limit walk, same run: "), std::string::npos);
    const double seconds = std::stod(cells[3]), median = std::stod(cells[11]), toTarget = std::stod(cells[12]);
    ASSERT_GT(median, 0.001) << "the test needs a render short of the target";
    ASSERT_LT(median, 1.0);
    EXPECT_NEAR(toTarget, seconds * (median / 0.001) * (median / 0.001), 0.01 * toTarget) << csv;
    EXPECT_NE(readText(s.dir / "t.md").find("time to 0.1 % (s)"), std::string::npos);
    r = printlight("bench " + scene.string() + " --self-variance --target-relative-error 2", s.dir);
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.err.find("--target-relative-error must be in (0, 1)"), std::string::npos) << r.err;
}

// The limit walk alone: no scene, its rate on the threads asked for.
TEST(Cli, BenchLimitWalk) {
    TestScene s("bench_limit");
    CliRun r = printlight("bench --limit --threads 1", s.dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("scattering events/s/core (20,000,000 events on 1 thread(s)"), std::string::npos) << r.out;
    r = printlight("bench", s.dir);
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.err.find("bench needs exactly one SCENE.json (or --limit alone)"), std::string::npos) << r.err;
}

TEST(Cli, BenchSelfVarianceAndConfigurationOverrides) {
    TestScene s("bench_self");
    fs::path scene = s.write();
    CliRun r = printlight("bench " + scene.string() + " --self-variance --spp 3 --configs volpath-separate,printpt-hero/k=1/rr_threshold=0.5 --out " +
                              (s.dir / "b").string(),
                          s.dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    std::string csv = readText(s.dir / "b.csv");
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 3) << csv;  // header + one row per configuration
    EXPECT_NE(csv.find("volpath-separate,1,3,"), std::string::npos) << csv;
    // Hero channels need two groups of three samples for a variance.
    EXPECT_NE(csv.find("printpt-hero/k=1/rr_threshold=0.5,1,6,"), std::string::npos) << csv;
    const std::string md = readText(s.dir / "b.md");
    EXPECT_NE(md.find("own variance estimate"), std::string::npos);
    // The per-channel table: separate passes only, each pass timed within
    // the render's time, the baseline (the first configuration) at 1.00.
    const size_t table = md.find("Per channel (separate passes)");
    ASSERT_NE(table, std::string::npos) << md;
    const std::string rowStart = "| volpath-separate | 1 | ", csvStart = "volpath-separate,1,3,";
    const size_t row = md.find(rowStart, table);
    ASSERT_NE(row, std::string::npos) << md;
    EXPECT_EQ(md.find("printpt-hero", table), std::string::npos) << md;
    std::istringstream cells(md.substr(row + rowStart.size()));
    double passR = 0, passG = 0, passB = 0;
    char bar = 0;
    cells >> passR >> bar >> passG >> bar >> passB;
    const double total = std::stod(csv.substr(csv.find(csvStart) + csvStart.size()));
    EXPECT_GT(passR, 0.0);
    EXPECT_GT(passG, 0.0);
    EXPECT_GT(passB, 0.0);
    EXPECT_LE(passR + passG + passB, total * 1.001 + 0.001) << md << csv;
    EXPECT_NE(md.find("| 1.00 | 1.00 | 1.00 |", row), std::string::npos) << md;
    // Overrides are checked.
    r = printlight("bench " + scene.string() + " --self-variance --configs printpt/bogus=1", s.dir);
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.err.find("bogus: not an option of printpt (its options: branches,"), std::string::npos) << r.err;
    r = printlight("bench " + scene.string() + " --self-variance --configs printpt/rr_threshold=0", s.dir);
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.err.find("rr_threshold: must be in (0, 1]"), std::string::npos) << r.err;
    r = printlight("bench " + scene.string() + " --self-variance --configs printpt/k=0", s.dir);
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.err.find("branches: must be a whole number"), std::string::npos) << r.err;
    r = printlight("bench " + scene.string() + " --self-variance --reference x.exr", s.dir);
    EXPECT_EQ(r.exitCode, 2);
}

// Self-variance relative MSE: printpt's k = 4 walks from a surface voxel's
// fixed entry are independent, so at equal spp k = 1 has 4x the variance per
// pixel. Relative to each render's own means (and relative to the other
// render's) the two came out equal on this black-and-white mix (ratio 0.99).
// With one pooled denominator k = 1 is clearly worse (2.6; below 4 because
// the pooled mean is mostly k = 4's, whose noise goes with its variance).
TEST(Cli, BenchSelfVarianceRelativeErrorFollowsTheVariance) {
    TestScene s("bench_rel");
    writeLabelGridBin(test::boxGrid({20, 20, 20}, {0.1f, 0.1f, 0.1f},
                                    [](const Vec3i& v) { return Label((v.x / 2 + v.y / 2 + v.z / 2) % 2 ? 3 : 4); }),
                      s.dir / "grid.bin");
    fs::path scene = s.write();
    CliRun r = printlight("bench " + scene.string() + " --self-variance --spp 4 --configs printpt,printpt/k=1 --out " +
                              (s.dir / "b").string(),
                          s.dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    // config,budget_s,spp,time_s,rmse_r,rmse_g,rmse_b,rmse,rel_mse,...
    auto rows = readCsvCells(s.dir / "b.csv");
    ASSERT_EQ(rows.size(), 2u);
    double rmse[2], relMse[2];
    for (int i = 0; i < 2; ++i) {
        ASSERT_GE(rows[i].size(), 9u);
        rmse[i] = std::stod(rows[i][7]);
        relMse[i] = std::stod(rows[i][8]);
    }
    const double mseRatio = (rmse[1] * rmse[1]) / (rmse[0] * rmse[0]), relRatio = relMse[1] / relMse[0];
    EXPECT_GT(mseRatio, 2.5);
    EXPECT_LT(mseRatio, 6.0);
    EXPECT_GT(relRatio, 2.0) << "MSE ratio " << mseRatio;
    EXPECT_LT(relRatio, 6.0) << "MSE ratio " << mseRatio;
}

// The shipped regression manifest: a rerun (other thread count) is bit for
// bit the stored result, another seed passes the statistical comparison, and
// a changed scene (3 % brighter surroundings) is reported as a regression.
TEST(Cli, BatchRegressionRendersOfTheBundledScenes) {
    fs::path dir = test::freshTempDir("cli_batch");
    std::string manifest = (test::sourceDir() / "data/batch/regression.json").string();
    CliRun r = printlight("batch " + manifest + " -o " + (dir / "stored").string() + " --quiet", dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    for (const char* name : {"cube10_greek_surface_printpt_g", "cube10_greek_preview_volpath", "cube10_white_preview_volpath"})
        EXPECT_TRUE(fs::exists(dir / "stored" / (std::string(name) + ".exr"))) << name;
    EXPECT_TRUE(fs::exists(dir / "stored" / "batch.csv"));

    r = printlight("batch " + manifest + " -o " + (dir / "rerun").string() + " --compare " + (dir / "stored").string() +
                       " --threads 1 --quiet", dir);
    EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
    EXPECT_EQ(test::countOf(r.out, "compare (exact): bit-identical -> pass"), 3) << r.out;

    r = printlight("batch " + manifest + " -o " + (dir / "seed").string() + " --compare " + (dir / "stored").string() +
                       " --seed-offset 1000 --quiet", dir);
    EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
    EXPECT_EQ(test::countOf(r.out, "compare (statistical): "), 3) << r.out;
    EXPECT_NE(readText(dir / "seed" / "batch.csv").find(",statistical,"), std::string::npos);

    // The preview scene with brighter surroundings, under the stored name.
    nlohmann::json scene = nlohmann::json::parse(readText(test::sourceDir() / "data/scenes/cube10_greek_preview.json"));
    for (const char* key : {"mesh", "labels", "materials"})
        scene["object"][key] = (test::sourceDir() / "data/scenes" / scene["object"][key].get<std::string>()).string();
    scene["environment"]["radiance"] = {1.03, 1.03, 1.03};
    writeText(dir / "brighter.json", scene.dump());
    writeText(dir / "changed.json", R"({"renders": [{"name": "cube10_greek_preview_volpath", "scene": "brighter.json",
                                        "spp": 8, "seed": 103}]})");
    r = printlight("batch " + (dir / "changed.json").string() + " -o " + (dir / "changed").string() + " --compare " +
                       (dir / "stored").string() + " --quiet", dir);
    EXPECT_EQ(r.exitCode, 1) << r.out << r.err;
    EXPECT_NE(r.out.find("-> FAIL"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("REGRESSION"), std::string::npos) << r.out;

    // Bad manifests and a compare directory that would be overwritten.
    writeText(dir / "bad.json", R"({"renders": [{"name": "../x", "scene": "brighter.json", "spp": 8, "seed": 1}]})");
    r = printlight("batch " + (dir / "bad.json").string() + " -o " + (dir / "bad").string(), dir);
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("bad.json"), std::string::npos) << r.err;
    EXPECT_EQ(test::countOf(r.err, "\n"), 1) << r.err;
    writeText(dir / "nospp.json", R"({"renders": [{"name": "x", "scene": "brighter.json", "seed": 1}]})");
    r = printlight("batch " + (dir / "nospp.json").string() + " -o " + (dir / "bad").string(), dir);
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("spp"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "bad"));
    r = printlight("batch " + manifest + " -o " + (dir / "stored").string() + " --compare " + (dir / "stored").string(), dir);
    EXPECT_EQ(r.exitCode, 1) << r.err;
}

// The quick subset of the numerical stability suite: every row passes
// (closed forms, furnace, Beer-Lambert, the other estimator, far from the
// origin, a missing label) and the report is written.
TEST(Cli, StabilityQuickSuitePasses) {
    fs::path dir = test::freshTempDir("cli_stability");
    CliRun r = printlight("stability --quick -o " + (dir / "stability.md").string(), dir);
    EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
    std::string md = readText(dir / "stability.md");
    EXPECT_NE(md.find("| far from origin |"), std::string::npos) << md;
    EXPECT_NE(md.find("| dense Beer-Lambert |"), std::string::npos) << md;
    EXPECT_EQ(md.find("FAIL"), std::string::npos) << md;
    EXPECT_EQ(test::countOf(r.out, "FAIL"), 0) << r.out;
}

TEST(Cli, PredictRunsTheApiLikeALoop) {
    TestScene s("predict");
    CliRun r = printlight("predict " + s.write().string() + " --iterations 2 --changes 20 --spp 1 --channel r", s.dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("iteration,update_s,render_s,update_share"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("2 iterations: update"), std::string::npos) << r.out;
    s.scene["sensor"] = {{"type", "perspective"}, {"position", {5, 5, 5}}, {"look_at", {1, 1, 1}}, {"resolution", {8, 8}}};
    r = printlight("predict " + s.write().string(), s.dir);
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("surface_voxels"), std::string::npos) << r.err;
}

TEST(Cli, OptimizeMovesAWhiteCubeTowardsATargetColour) {
    TestScene s("optimize");
    fs::path prefix = s.dir / "out" / "opt";
    CliRun r = printlight("optimize " + s.write().string() + smallGamut(s) +
                              " --target 0.2,0.45,0.8 --iterations 8 --spp 4 -o " + prefix.string(),
                          s.dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    auto rows = readCsvNumbers(prefix.string() + ".csv");
    ASSERT_GE(rows.size(), 3u);
    ASSERT_LE(rows.size(), 9u);  // at most 8 iterations; it may stop sooner
    // All white at first; a blue the shell can print is far closer once
    // the characterised mixtures are printed, and the loop does not make
    // it worse again by more than its noise.
    EXPECT_GT(rows[0][1], 20.0);
    EXPECT_LT(rows[1][1], 0.5 * rows[0][1]) << r.out;
    for (size_t i = 2; i < rows.size(); ++i) EXPECT_LT(rows[i][1], rows[i - 1][1] + rows[i][8]) << r.out;
    EXPECT_GT(rows[1][6], 0.0);  // labels changed
    // The samples: 4 as asked, 4x more (the most, 8 by default) once the
    // score stalls, 32 only where the predictions' noise over the
    // footprint was still above 2 at 8; never fewer again.
    for (size_t i = 0; i < rows.size(); ++i) {
        EXPECT_TRUE(rows[i][11] == 4.0 || rows[i][11] == 8.0 || rows[i][11] == 32.0) << r.out;
        if (i > 0) {
            EXPECT_GE(rows[i][11], rows[i - 1][11]) << r.out;
            if (rows[i][11] == 32.0 && rows[i - 1][11] == 8.0) {
                EXPECT_GT(rows[i - 1][8], 2.0) << r.out;
            }
        }
    }
    EXPECT_NE(r.out.find("mapping loss (the target as given -> printable colours, colorimetric intent)"),
              std::string::npos)
        << r.out;
    // The judge by default: 64 sampled footprints, in rounds until its
    // noise over the footprint is under 0.5, or its most samples; the mean
    // error with its 95 % interval.
    const size_t judgeAt = r.out.find("the judge's own noise (its two halves' disagreement): ");
    ASSERT_NE(judgeAt, std::string::npos) << r.out;
    double judgeNoise = 0, judged = 0, halfWidth = 0;
    unsigned judgeSpp = 0;
    size_t rendered = 0;
    ASSERT_EQ(std::sscanf(r.out.c_str() + judgeAt + 54, "%lf", &judgeNoise), 1) << r.out;
    const std::string sampled = "judged apart on 64 footprints sampled over the surface (volpath, ";
    const size_t sampledAt = r.out.find(sampled);
    ASSERT_NE(sampledAt, std::string::npos) << r.out;
    ASSERT_EQ(std::sscanf(r.out.c_str() + sampledAt + sampled.size(), "%zu voxels, %u spp", &rendered, &judgeSpp), 2)
        << r.out;
    EXPECT_GT(rendered, 0u) << r.out;
    EXPECT_TRUE(judgeNoise <= 0.5 || judgeSpp >= 256) << r.out;
    ASSERT_EQ(std::sscanf(r.out.c_str() + r.out.find("0.2 mm footprint ", sampledAt) + 17, "%lf +- %lf", &judged,
                          &halfWidth),
              2)
        << r.out;
    EXPECT_GT(halfWidth, 0.0) << r.out;
    EXPECT_LT(judged, 0.6 * rows[0][1]) << r.out;
    LabelGrid labels = loadLabelGrid(prefix.string() + "_labels.vdb", std::nullopt);
    EXPECT_EQ(labels.frame().resolution, (Vec3i{20, 20, 20}));
    EXPECT_LT(labels.histogram()[4], 20u * 20 * 20);  // no longer all white
    // The best iteration on the model, and the page with the history.
    for (const char* part : {"_target.glb", "_mapped.glb", "_prediction.glb", "_error.glb", "_mapping_loss.glb",
                             "_error_from_given.glb", "_printers_limit.glb"})
        EXPECT_GT(fs::file_size(prefix.string() + part), 1000u) << part;
    const std::string page = readText(prefix.string() + ".html");
    for (const char* label : {"\"target\"", "\"target mapped\"", "\"prediction\"", "\"CIEDE2000\"",
                              "\"mapping loss (CIEDE2000, given -> mapped)\"", "\"from the target as given (CIEDE2000)\"",
                              "\"at the printer's limit (magenta)\""})
        EXPECT_NE(page.find(label), std::string::npos) << label;
    EXPECT_NE(page.find("from the target as given "), std::string::npos);
    EXPECT_NE(page.find("\"history\":[{\"iteration\":0.0"), std::string::npos);
    EXPECT_FALSE(fs::exists(s.dir / "cache" / "printlight"));  // the named characterisation, none made
    CliRun bad = printlight("optimize " + s.write().string() + " --target 2,0,0", s.dir);
    EXPECT_EQ(bad.exitCode, 2) << bad.err;
    EXPECT_NE(bad.err.find("--target"), std::string::npos) << bad.err;
    CliRun noGamut = printlight("optimize " + s.write().string() + " --target 0.2,0.45,0.8 --gamut " +
                                    (s.dir / "none.json").string(), s.dir);
    EXPECT_EQ(noGamut.exitCode, 1) << noGamut.err;
    EXPECT_NE(noGamut.err.find("none.json"), std::string::npos) << noGamut.err;
}

// Halftoning by thresholds and predictions that carry over, end to end:
// each method runs the loop, the CSV says how many surface voxels each
// iteration traced again, and unknown names are usage errors; the loop's
// label changes, recorded, are replayed by bench --loop.
TEST(Cli, OptimizeByThresholdsWithPredictionsThatCarryOver) {
    TestScene s("optimize_carry_over");
    const fs::path changes = s.dir / "out" / "changes.bin";
    for (const char* method : {"kept", "control-variates"}) {
        fs::path prefix = s.dir / "out" / method;
        CliRun r = printlight("optimize " + s.write().string() + smallGamut(s) +
                                  " --target 0.2,0.45,0.8 --iterations 3 --spp 3 --judge-spp 2 --halftone thresholds "
                                  "--hysteresis 0.01 --carry-over " + method + " --record-changes " +
                                  changes.string() + " -o " + prefix.string(),
                              s.dir);
        ASSERT_EQ(r.exitCode, 0) << r.err;
        const auto rows = readCsvNumbers(prefix.string() + ".csv");
        ASSERT_GE(rows.size(), 3u) << method;
        EXPECT_GT(rows[0][1], 20.0) << method;
        EXPECT_LT(rows[1][1], 0.5 * rows[0][1]) << method << r.out;
        EXPECT_EQ(rows[0][12], 0.0) << method;  // the first prediction starts afresh
        EXPECT_GT(rows[1][12], 0.0) << method;  // the first print reaches every voxel
        // Kept samples accumulate: 3 more each iteration.
        if (std::string(method) == "kept") {
            EXPECT_EQ(rows[1][13], 6.0) << r.out;
        } else {
            EXPECT_EQ(rows[1][13], 3.0) << r.out;
        }
    }
    // The recorded changes replayed: a row per prediction (3 iterations: 4).
    CliRun loop = printlight("bench " + s.write().string() + " --loop " + changes.string() +
                                 " --carry-over none,control-variates --spp 2 --out " + (s.dir / "out" / "b").string(),
                             s.dir);
    ASSERT_EQ(loop.exitCode, 0) << loop.err;
    EXPECT_NE(loop.out.find("| iteration | none | control-variates |"), std::string::npos) << loop.out;
    EXPECT_NE(loop.out.find("\n| 3 | "), std::string::npos) << loop.out;
    EXPECT_TRUE(fs::exists(s.dir / "out" / "b_loop.md"));
    std::ofstream(s.dir / "out" / "junk.bin") << "not changes";
    CliRun junk = printlight("bench " + s.write().string() + " --loop " + (s.dir / "out" / "junk.bin").string(), s.dir);
    EXPECT_EQ(junk.exitCode, 1) << junk.err;
    EXPECT_NE(junk.err.find("junk.bin"), std::string::npos) << junk.err;
    for (const char* bad : {" --carry-over sometimes", " --halftone dots", " --hysteresis 0.7", " --intent vivid",
                            " --intent perceptual --no-gamut-map"}) {
        CliRun r = printlight("optimize " + s.write().string() + " --target 0.2,0.45,0.8" + bad, s.dir);
        EXPECT_EQ(r.exitCode, 2) << bad << r.err;
        EXPECT_NE(r.err.find(std::string(bad).substr(1, std::string(bad).find(' ', 1) - 1)), std::string::npos)
            << r.err;
    }
}

// The fast predictor first, then Monte Carlo, and the final labels judged
// apart: a blue the shell can print is far closer than the white it
// started from, as the judge sees it too, per voxel and over the eye's
// footprint.
TEST(Cli, OptimizeWithTheFastPredictorIsJudgedApart) {
    TestScene s("optimize_auto");
    fs::path prefix = s.dir / "out" / "opt";
    CliRun r = printlight("optimize " + s.write().string() + smallGamut(s) +
                              " --target 0.2,0.45,0.8 --iterations 6 --predictor auto --judge-spp 8 --judge-footprints 0 "
                              "--intent perceptual -o " +
                                  prefix.string(),
                          s.dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto cells = readCsvCells(prefix.string() + ".csv");
    ASSERT_GE(cells.size(), 3u);  // iterations 0-6, or fewer once the score stops falling
    ASSERT_LE(cells.size(), 7u);
    EXPECT_NE(r.out.find("perceptual intent"), std::string::npos) << r.out;
    EXPECT_EQ(cells[0][7], "diffusion");
    EXPECT_EQ(cells.back()[7], "volpath");  // Monte Carlo by the end (diffusion's score flattens)
    const auto rows = readCsvNumbers(prefix.string() + ".csv");
    const size_t at = r.out.find("judged apart (volpath, 8 spp in 1 round, seed 99");
    ASSERT_NE(at, std::string::npos) << r.out;
    double perVoxel = 0, p95 = 0, filtered = 0;
    ASSERT_EQ(std::sscanf(r.out.c_str() + r.out.find("footprint", at),
                          "footprint %lf, 95th percentile %lf; per voxel %lf", &filtered, &p95, &perVoxel),
              3)
        << r.out;
    EXPECT_LT(filtered, 0.6 * rows[0][1]) << r.out;
    EXPECT_LE(filtered, perVoxel) << r.out;  // averaging over the footprint removes noise
    double noise = 0, noiseRemoved = 0;
    const size_t noiseAt = r.out.find("the judge's own noise (its two halves' disagreement): ");
    ASSERT_NE(noiseAt, std::string::npos) << r.out;
    ASSERT_EQ(std::sscanf(r.out.c_str() + noiseAt + 54, "%lf", &noise), 1) << r.out;
    ASSERT_EQ(std::sscanf(r.out.c_str() + r.out.find("root mean square over the footprint is ", noiseAt) + 39, "%lf",
                          &noiseRemoved),
              1)
        << r.out;
    EXPECT_GT(noise, 0.0) << r.out;
    EXPECT_LT(noiseRemoved, 0.6 * rows[0][1]) << r.out;
    CliRun bad = printlight("optimize " + s.write().string() + " --target 0.2,0.45,0.8 --predictor fast", s.dir);
    EXPECT_EQ(bad.exitCode, 2) << bad.err;
    EXPECT_NE(bad.err.find("--predictor"), std::string::npos) << bad.err;
}

// The learned predictor reads the model beside the material table, or the
// one the scene names; without one, or for voxels it was not trained for
// (this cube's 0.1 mm), it says so in one line and writes nothing.
TEST(Cli, LearnedPredictorRefusesWithoutItsModel) {
    TestScene s("learned_refusal");
    s.scene["render"]["reentry"] = false;
    s.scene["render"]["integrator"] = "learned";
    expectCleanFailure(s, s.render(), "materials.learned.json", "no learned model");
    // Its voxels are known once the scene is loaded: after the summary line.
    s.scene["render"]["learned_model"] =
        (test::sourceDir() / "data/materials/resins_illustrative.learned.json").string();
    const CliRun r = s.render();
    EXPECT_EQ(r.exitCode, 1) << r.err;
    const size_t last = r.err.rfind("printlight: error: ");
    ASSERT_NE(last, std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin() + std::ptrdiff_t(last), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find("trained for 0.0423 x 0.0847 x 0.027 mm voxels", last), std::string::npos) << r.err;
    EXPECT_FALSE(s.anyOutput());
}

TEST(Cli, OptimizeReducesTheErrorOnTheDetailedCube) {
    TestScene s("optimize_greek");
    fs::path prefix = s.dir / "opt";
    CliRun r = printlight("optimize " + (test::sourceDir() / "data/scenes/cube10_greek_surface.json").string() +
                              " --target " + (test::sourceDir() / "data/models/cube10_greek.gltf").string() +
                              " --iterations 1 --spp 1 --judge-spp 0 -o " + prefix.string(), s.dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    auto rows = readCsvNumbers(prefix.string() + ".csv");
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_LT(rows[1][1], 0.9 * rows[0][1]) << r.out;
}

TEST(Cli, InfoDescribesABundledGrid) {
    TestScene s("info");
    CliRun r = printlight("info " + (test::sourceDir() / "data/grids/cube10_white.vdb").string(), s.dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("243 x 121 x 380"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("white"), std::string::npos);
    EXPECT_NE(r.out.find("ratio x"), std::string::npos);
    CliRun bad = printlight("info " + (s.dir / "nothing.vdb").string(), s.dir);
    EXPECT_EQ(bad.exitCode, 1);
    EXPECT_NE(bad.err.find("nothing.vdb"), std::string::npos);
}

}  // namespace
}  // namespace pl
