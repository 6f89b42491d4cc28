// The command line as a user meets it: exit status 2 and one line naming the key on bad input,
// no run directory left behind, JSON alone on stdout with --json.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <tuple>

#include "names.hpp"
#include "paths.hpp"
#include "scratch.hpp"

namespace fs = std::filesystem;

namespace {

struct Outcome {
  int status = -1;
  std::string out, err;
};

// Each test runs in its own process (gtest_discover_tests), so each makes its own scratch folder
// (tests/scratch.hpp), removed when the process ends, pass or fail: no run leaves anything in /tmp.
const fs::path& scratch() {
  static const rotleak::test::ScratchDir dir("rotleak_cli_test_");
  static const bool made = fs::create_directories(dir.path);
  (void)made;
  return dir.path;
}

std::string slurp(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

Outcome run(const std::string& args) {
  const fs::path out = scratch() / "stdout.txt", err = scratch() / "stderr.txt";
  const std::string cmd =
      std::string(rotleak::test::rotleak_binary()) + " " + args + " >" + out.string() + " 2>" + err.string();
  const int raw = std::system(cmd.c_str());
  Outcome o;
  o.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  o.out = slurp(out);
  o.err = slurp(err);
  return o;
}

fs::path write_scene(const std::string& name, const std::string& text) {
  const fs::path p = scratch() / name;
  std::ofstream(p) << text;
  return p;
}

const char* kSmall = "[ensemble]\nparticles = 2000\n[run]\nt_max = 400\n[fit]\nkappa_window = [0, 300]\n";

}  // namespace

class CliBadInput : public ::testing::TestWithParam<std::pair<std::string, std::string>> {};

TEST_P(CliBadInput, ExitsWithStatusTwoAndOneLineNamingTheKey) {
  const auto& [extra, key] = GetParam();
  const fs::path scene = write_scene("small.toml", kSmall);
  const fs::path outdir = scratch() / "bad_run";
  fs::remove_all(outdir);
  const Outcome o = run("simulate " + scene.string() + " --out " + outdir.string() + " " + extra);
  EXPECT_EQ(o.status, 2) << o.err;
  EXPECT_NE(o.err.find(key), std::string::npos) << o.err;
  EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << o.err;
  EXPECT_FALSE(fs::exists(outdir)) << "a run directory was left behind";
  EXPECT_TRUE(o.out.empty());
}

INSTANTIATE_TEST_SUITE_P(Cases, CliBadInput,
                         ::testing::Values(std::pair{std::string("--set leak.width=1"), std::string("leak.width")},
                                           std::pair{std::string("--set leak.omega=foo"), std::string("leak.omega")},
                                           std::pair{std::string("--set run.t_max=0"), std::string("run.t_max")},
                                           std::pair{std::string("--set run.t_max=nan"), std::string("run.t_max")},
                                           std::pair{std::string("--set stadium.r=-1"), std::string("stadium.r")},
                                           std::pair{std::string("--particles 0"), std::string("--particles")},
                                           std::pair{std::string("--set leak.colour=red"), std::string("leak.colour")},
                                           std::pair{std::string("--threads -1"), std::string("--threads")},
                                           // once silently ignored
                                           std::pair{std::string("--particles -5"), std::string("--particles")},
                                           // once started 10000 threads / aborted in bad_alloc
                                           std::pair{std::string("--threads 10000"), std::string("--threads")},
                                           std::pair{std::string("--set ensemble.particles=10000000000000 --set "
                                                                 "observe.escapes=true"),
                                                     std::string("ensemble.particles")},
                                           // an undecidable value once exited 1 without the key
                                           std::pair{std::string("--set stadium.d=pi-pi"), std::string("stadium.d")},
                                           std::pair{std::string("--bogus"), std::string("--bogus")},
                                           // crashes (rc 139): an error path dereferenced a key never given
                                           std::pair{std::string("--set run.t_max=1"),
                                                     std::string("ensemble.creation_window = 4.0 (the default)")},
                                           std::pair{std::string("--set run.splitting=true --set "
                                                                 "ensemble.sampling=mupo --set run.t_max=100"),
                                                     std::string("run.split_every")},
                                           // a confident wrong number: splitting on uniform draws
                                           std::pair{std::string("--set run.splitting=true"),
                                                     std::string("ensemble.sampling = \"mupo\"")},
                                           // the message blamed stadium.r, never given
                                           std::pair{std::string("--set run.t_max=1e12"), std::string("run.t_max")}),
                         rotleak::test::IndexedName());

TEST(Cli, ADirectoryIsNotAScene) {  // it once ran a default scene, exit 0
  const Outcome o = run("simulate " + scratch().string() + " --out " + (scratch() / "from_dir").string());
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.err.find("SCENE"), std::string::npos) << o.err;
  EXPECT_FALSE(fs::exists(scratch() / "from_dir"));
}

TEST(Cli, JsonWithPlotKeepsStdoutOneDocument) {  // "drew ..." once followed the JSON on stdout
  const fs::path scene = write_scene("small.toml", kSmall);
  const fs::path o = scratch() / "json_plot";
  fs::remove_all(o);
  const Outcome r = run("simulate " + scene.string() + " --out " + o.string() + " --json --plot");
  ASSERT_EQ(r.status, 0) << r.err;
  nlohmann::json doc;
  EXPECT_NO_THROW(doc = nlohmann::json::parse(r.out)) << r.out;
  EXPECT_TRUE(doc.contains("kappa"));
}

// Messages quote what the user wrote: a whole UTF-8 character, a float with its point; a long
// expansion that needs more than the default working precision is computed, not refused.
TEST(Cli, MessagesQuoteInputAsWritten) {
  const Outcome half = run("omega '\xc2\xbd'");
  EXPECT_EQ(half.status, 2);
  EXPECT_NE(half.err.find("'\xc2\xbd'"), std::string::npos) << half.err;
  const fs::path scene = write_scene("small.toml", kSmall);
  const Outcome dt =
      run("simulate " + scene.string() + " --out " + (scratch() / "dt").string() + " --set observe.survival_dt=-1.0");
  EXPECT_EQ(dt.status, 2);
  EXPECT_NE(dt.err.find("= -1.0:"), std::string::npos) << dt.err;
  const Outcome terms = run("omega 'ln(19)' --terms 20000 --json");
  ASSERT_EQ(terms.status, 0) << terms.err;
  EXPECT_EQ(nlohmann::json::parse(terms.out)["omega"]["certified_terms"], 20000);
}

// A scene path that is not UTF-8 once simulated 4.3 s, then failed in the JSON writer with a raw exception (rc 1,
// nothing kept): refused before any work, rc 2, one line showing the odd byte.
TEST(Cli, ANonUtf8PathIsRefusedBeforeAnyWork) {
  const fs::path dir = scratch() / std::string(
                                       "bad\xff"
                                       "name");
  fs::create_directories(dir);
  fs::copy_file(write_scene("small.toml", kSmall), dir / "s.toml", fs::copy_options::overwrite_existing);
  const fs::path outdir = scratch() / "non_utf8_run";
  const Outcome o = run("simulate \"" + (dir / "s.toml").string() + "\" --out " + outdir.string());
  EXPECT_EQ(o.status, 2) << o.err;
  EXPECT_NE(o.err.find("bad\\xffname"), std::string::npos) << o.err;
  EXPECT_NE(o.err.find("not valid UTF-8"), std::string::npos) << o.err;
  EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << o.err;
  EXPECT_FALSE(fs::exists(outdir));
}

// rotleak fit printed three of the lines simulate prints of its fits (no window systematic, z, C, model line):
// a refit under the same keys prints simulate's fit lines, word for word.
TEST(Cli, FitPrintsTheFitsAsSimulateDoes) {
  const fs::path scene = write_scene("small.toml", kSmall);
  const fs::path dir = scratch() / "fit_text";
  fs::remove_all(dir);
  const Outcome sim =
      run("simulate " + scene.string() + " --set leak.omega=2/3 --out " + dir.string() + " --no-progress");
  ASSERT_EQ(sim.status, 0) << sim.err;
  const Outcome fit = run("fit " + dir.string());
  ASSERT_EQ(fit.status, 0) << fit.err;
  const std::size_t from = sim.out.find("kappa = "), to = sim.out.find("wrote ");
  ASSERT_NE(from, std::string::npos) << sim.out;
  ASSERT_NE(to, std::string::npos) << sim.out;
  EXPECT_EQ(fit.out.substr(0, fit.out.find("rewrote ")), sim.out.substr(from, to - from));
}

// --force over a read-only earlier run printed "wrote", rc 0, and left the old run as .NAME.partial-N: now it is
// refused before any work, naming the directory it cannot write, and nothing changes. Root writes anywhere, so the
// second run is made as the user nobody (setpriv, util-linux), over a run nobody owns and cannot write.
TEST(Cli, ForceOverAReadOnlyRunIsRefusedBeforeAnyWork) {
  if (::geteuid() != 0 || std::system("command -v setpriv >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "needs root and setpriv to run as another user";
  const fs::path scene = write_scene("small.toml", kSmall);
  const fs::path dir = scratch() / "read_only_run";
  fs::remove_all(dir);
  ASSERT_EQ(run("simulate " + scene.string() + " --out " + dir.string() + " --no-progress").status, 0);
  const std::string before = slurp(dir / "survival.csv");
  fs::permissions(scratch(), fs::perms::all);  // nobody may make its lock and staging beside the run
  ASSERT_EQ(std::system(("chown -R 65534 " + dir.string() + " && chmod -R a-w " + dir.string()).c_str()), 0);
  const fs::path err = scratch() / "ro_err.txt";
  const std::string cmd = "setpriv --reuid=65534 --regid=65534 --clear-groups " +
                          std::string(rotleak::test::rotleak_binary()) + " simulate " + scene.string() +
                          " --set ensemble.seed=2 --force --no-progress --out " + dir.string() + " >/dev/null 2>" +
                          err.string();
  const int raw = std::system(cmd.c_str());
  const std::string e = slurp(err);
  EXPECT_EQ(WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, 2) << e;
  EXPECT_NE(e.find("is not writable"), std::string::npos) << e;
  EXPECT_EQ(std::count(e.begin(), e.end(), '\n'), 1) << e;
  EXPECT_EQ(slurp(dir / "survival.csv"), before);
  for (const auto& entry : fs::directory_iterator(scratch()))
    EXPECT_EQ(entry.path().filename().string().find(".read_only_run.partial-"), std::string::npos) << entry.path();
  std::system(("chmod -R u+w " + dir.string()).c_str());  // the scratch folder is removed whole after the tests
}

// certify's precision options each blame themselves (--max-bits 100000000 once blamed --bits), in one line, rc 2.
TEST(Cli, CertifyBitsBlameTheirOwnOption) {
  const fs::path scene = write_scene("small.toml", kSmall);
  for (const auto& [args, key] :
       {std::pair{"--max-bits 100000000", "--max-bits = 100000000"}, std::pair{"--max-bits 8", "--max-bits = 8"},
        std::pair{"--bits 10", "--bits = 10"}, std::pair{"--bits 4096 --max-bits 1024", "--bits = 4096"}}) {
    const Outcome o = run("certify " + scene.string() + " --particle 1 " + args);
    EXPECT_EQ(o.status, 2) << args << ": " << o.err;
    EXPECT_NE(o.err.find(key), std::string::npos) << o.err;
    EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << o.err;
  }
}

// A plot of a damaged directory is one line on stderr and exit 2 (bad input, as rotleak fit says it), no
// traceback, no half picture.
TEST(Cli, PlotFailureIsOneLine) {
  const fs::path bad = scratch() / "bad_run";
  fs::create_directories(bad);
  std::ofstream(bad / "summary.json") << "{";
  const Outcome o = run("plot " + bad.string());
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.err.find("summary.json: not valid JSON (damaged or truncated)"), std::string::npos) << o.err;
  EXPECT_EQ(o.err.find("Traceback"), std::string::npos) << o.err;
  EXPECT_NE(o.err.find("cannot draw"), std::string::npos) << o.err;
  for (const auto& e : fs::directory_iterator(bad)) EXPECT_EQ(e.path().extension(), ".json") << e.path();
}

TEST(Cli, MissingSceneFileIsBadInput) {
  const Outcome o = run("simulate /nonexistent/scene.toml --out " + (scratch() / "x").string());
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.err.find("/nonexistent/scene.toml"), std::string::npos);
}

TEST(Cli, ExistingOutputNeedsForceAndJsonIsAloneOnStdout) {
  const fs::path scene = write_scene("small.toml", kSmall);
  const fs::path outdir = scratch() / "run_ok";
  fs::remove_all(outdir);
  const Outcome first = run("simulate " + scene.string() + " --out " + outdir.string() + " --json --threads 2");
  ASSERT_EQ(first.status, 0) << first.err;
  const auto j = nlohmann::json::parse(first.out);  // throws if anything else is on stdout
  for (const char* key : {"seed", "execution", "collisions", "kappa", "alpha", "scene", "tier"})
    EXPECT_TRUE(j.contains(key)) << key;
  for (const char* key : {"rotleak", "host", "engine", "threads", "ranks", "wall_seconds", "collisions_per_second"})
    EXPECT_TRUE(j["execution"].contains(key)) << "execution." << key;
  EXPECT_EQ(j["execution"]["threads"], 2);
  EXPECT_TRUE(j["kappa"].contains("value"));
  EXPECT_TRUE(j["kappa"].contains("error"));
  EXPECT_TRUE(j["alpha"].contains("value"));
  EXPECT_EQ(j["particles"], 2000);
  EXPECT_EQ(slurp(outdir / "survival.csv").substr(0, 20), "t,survivors,P,P_err\n");
  EXPECT_EQ(nlohmann::json::parse(slurp(outdir / "summary.json")), j);

  const Outcome again = run("simulate " + scene.string() + " --out " + outdir.string());
  EXPECT_EQ(again.status, 2);
  EXPECT_NE(again.err.find("--force"), std::string::npos);
  EXPECT_TRUE(fs::exists(outdir / "summary.json")) << "the old run must survive a refused overwrite";

  const Outcome forced =
      run("simulate " + scene.string() + " --out " + outdir.string() + " --force --set ensemble.seed=7");
  EXPECT_EQ(forced.status, 0) << forced.err;
  EXPECT_EQ(nlohmann::json::parse(slurp(outdir / "summary.json"))["seed"], 7);
  for (const auto& e : fs::directory_iterator(scratch()))
    EXPECT_EQ(e.path().filename().string().find(".partial-"), std::string::npos) << e.path();
}

TEST(Cli, RefusesToReplaceADirectoryThatIsNotARun) {
  const fs::path scene = write_scene("small.toml", kSmall);
  const fs::path precious = scratch() / "precious";
  fs::create_directories(precious);
  std::ofstream(precious / "notes.txt") << "keep me";
  const Outcome o = run("simulate " + scene.string() + " --out " + precious.string() + " --force");
  EXPECT_EQ(o.status, 2);
  EXPECT_TRUE(fs::exists(precious / "notes.txt"));
}

// A trailing slash names the same directory: replacing "o" through "o/" keeps a complete run there
// (it once deleted the old run and wrote nothing).
TEST(Cli, TrailingSlashReplacesTheRunInPlace) {
  const fs::path scene = write_scene("small.toml", kSmall);
  const fs::path o = scratch() / "slash";
  fs::remove_all(o);
  ASSERT_EQ(run("simulate " + scene.string() + " --out " + o.string()).status, 0);
  const Outcome again = run("simulate " + scene.string() + " --out " + o.string() + "/ --force --set ensemble.seed=3");
  EXPECT_EQ(again.status, 0) << again.err;
  ASSERT_TRUE(fs::exists(o / "summary.json"));
  EXPECT_EQ(nlohmann::json::parse(slurp(o / "summary.json"))["seed"], 3);
}

// A directory held by a live run is refused (the lock), and what a killed run left is cleaned by the
// next run into the same target.
TEST(Cli, ASecondRunIntoTheSameDirectoryIsRefusedAndLeftoversAreCleaned) {
  const fs::path scene = write_scene("small.toml", kSmall);
  const fs::path o = scratch() / "locked";
  fs::remove_all(o);
  const int fd = ::open((scratch() / ".locked.lock").c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX), 0);  // as a running rotleak holds it
  const Outcome held = run("simulate " + scene.string() + " --out " + o.string());
  EXPECT_EQ(held.status, 2);
  EXPECT_NE(held.err.find("another rotleak run"), std::string::npos) << held.err;
  EXPECT_FALSE(fs::exists(o));
  ::close(fd);
  fs::create_directories(scratch() / ".locked.partial-999999");  // as a killed run leaves it
  const Outcome free = run("simulate " + scene.string() + " --out " + o.string());
  EXPECT_EQ(free.status, 0) << free.err;
  EXPECT_FALSE(fs::exists(scratch() / ".locked.partial-999999"));
  EXPECT_FALSE(fs::exists(scratch() / ".locked.lock"));
}

// An input error found after the output was staged leaves no directory behind, parents included.
TEST(Cli, AFailedRunLeavesNoParentsBehind) {
  const fs::path top = scratch() / "np";
  fs::remove_all(top);
  const Outcome o = run("covering --omega 2/3 --delta 1e-20 --out " + (top / "a" / "b" / "c").string());
  EXPECT_EQ(o.status, 2);
  EXPECT_FALSE(fs::exists(top));
}

class CliOmegaBadInput : public ::testing::TestWithParam<std::pair<std::string, std::string>> {};

TEST_P(CliOmegaBadInput, ExitsWithStatusTwoNamingTheInput) {
  const auto& [args, key] = GetParam();
  const Outcome o = run(args);
  EXPECT_EQ(o.status, 2) << args << ": " << o.err;
  EXPECT_NE(o.err.find(key), std::string::npos) << o.err;
  EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << o.err;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, CliOmegaBadInput,
    ::testing::Values(std::pair{std::string("omega 'two thirds'"), std::string("omega")},
                      std::pair{std::string("omega 'ln(-2)'"), std::string("omega")},
                      std::pair{std::string("omega 2/3 --terms 0"), std::string("--terms")},
                      std::pair{std::string("omega 2/3 --max-den x"), std::string("--max-den")},
                      std::pair{std::string("omega 2/3 --eps 0"), std::string("--eps")},
                      std::pair{std::string("covering --omega foo"), std::string("--omega")},
                      std::pair{std::string("covering --omega 2/3 --delta 0"), std::string("--delta")},
                      std::pair{std::string("covering --omega 2/3 --delta 1"), std::string("--delta")},
                      std::pair{std::string("covering --omega 2/3 --lambda 1.5"), std::string("--lambda")},
                      std::pair{std::string("covering --omega 2/3 --lambda 0"), std::string("--lambda")},
                      std::pair{std::string("covering --omega 2/3 --delta 1e-20"), std::string("--delta")},
                      std::pair{std::string("omega pi-pi"), std::string("omega")}),
    rotleak::test::IndexedName());

TEST(Cli, OmegaAndCoveringJson) {
  const Outcome o = run("omega 'ln(19)' --terms 40 --json");
  ASSERT_EQ(o.status, 0) << o.err;
  const auto j = nlohmann::json::parse(o.out);
  EXPECT_EQ(j["omega"]["cf"].size(), 40u);
  EXPECT_EQ(j["omega"]["certified_terms"], 40);
  EXPECT_EQ(j["omega"]["convergents"][2], nlohmann::json::array({"50", "17"}));
  const Outcome c = run("covering --omega 2/3 --delta 1e-7 --lambda 0.01 --json");
  ASSERT_EQ(c.status, 0) << c.err;
  const auto k = nlohmann::json::parse(c.out)["covering"];
  for (const char* key : {"zero_measure", "max_zero_gap", "gaps", "discrepancy", "clusters"})
    EXPECT_TRUE(k.contains(key)) << key;
  EXPECT_EQ(k["clusters"], 3);
  const Outcome several = run("covering --omega 1 2/3 --json");
  ASSERT_EQ(several.status, 0) << several.err;
  EXPECT_EQ(nlohmann::json::parse(several.out)["covering"].size(), 2u);
}

// covering with several deltas: each omega at each delta, each entry naming its delta, and the same
// numbers as separate one-delta calls (ln(19): gaps at delta = 1e-7, none at 1e-9).
TEST(Cli, CoveringAtSeveralDeltas) {
  const Outcome both = run("covering --omega 2/3 'ln(19)' --delta 1e-7 1e-9 --json");
  ASSERT_EQ(both.status, 0) << both.err;
  const auto doc = nlohmann::json::parse(both.out);
  ASSERT_EQ(doc.at("covering").size(), 4u);
  EXPECT_EQ(doc.at("covering")[3].at("delta"), "1e-9");
  for (const auto& [omega, delta, index] : {std::tuple{"2/3", "1e-7", 0}, std::tuple{"'ln(19)'", "1e-9", 3}}) {
    const auto one =
        nlohmann::json::parse(run(std::string("covering --omega ") + omega + " --delta " + delta + " --json").out);
    EXPECT_EQ(one.at("covering").at("zero_measure"), doc.at("covering")[index].at("zero_measure")) << omega;
  }
  EXPECT_GT(doc.at("covering")[2].at("zero_measure").get<double>(), 0.5);  // ln(19) at 1e-7
  EXPECT_EQ(doc.at("covering")[3].at("zero_measure").get<double>(), 0.0);  // ln(19) at 1e-9
}

// Counts are exact texts: --particles 2e3 is 2000 (help and docs write 1e6); 1.5 and 0 are refused
// naming the key.
TEST(Cli, CountsTakeExponentNotation) {
  const fs::path scene = write_scene("small.toml", kSmall);
  const fs::path out = scratch() / "count_2e3";
  fs::remove_all(out);
  const Outcome ok = run("simulate " + scene.string() + " --particles 2e3 --out " + out.string() + " --json");
  ASSERT_EQ(ok.status, 0) << ok.err;
  EXPECT_EQ(nlohmann::json::parse(ok.out).at("particles"), 2000);
  for (const char* bad : {"1.5", "0", "1e30", "abc"}) {
    const Outcome o =
        run("simulate " + scene.string() + " --particles " + bad + " --out " + (scratch() / "c").string());
    EXPECT_EQ(o.status, 2) << bad;
    EXPECT_EQ(o.err.rfind(std::string("rotleak: error: --particles = ") + bad + ":", 0), 0u) << o.err;
  }
}

// rotleak plot draws every kind of directory rotleak writes: a run, a scan, a shadow, a covering (two
// deltas: one panel each) and a regimes search, as PNG and PDF with a caption line each; anything else is one line
// and exit 2, and so is a format it does not write.
TEST(Cli, PlotDrawsEveryKindOfDirectory) {
  const fs::path scene = write_scene("small.toml", kSmall);
  const fs::path base = scratch() / "plots";
  fs::remove_all(base);
  const std::string s = scene.string(), b = base.string();
  ASSERT_EQ(run("simulate " + s + " --out " + b + "/run").status, 0);
  ASSERT_EQ(run("scan " + s + " --over leak.omega=0,1 --out " + b + "/scan --no-progress").status, 0);
  ASSERT_EQ(run("shadow " + s + " --particle 3 --tiers float,double --collisions 200 --out " + b + "/shadow").status,
            0);
  ASSERT_EQ(run("covering --omega 2/3 1e-4 --delta 1e-7 1e-9 --resolution 100 --out " + b + "/covering").status, 0);
  ASSERT_EQ(run("regimes " + s + " --coarse 1e-3,1e-1 --steps 1 --out " + b + "/regimes").status, 0);
  for (const auto& [dir, picture] : {std::pair{"run", "survival.png"},
                                     {"scan", "scan_survival.png"},
                                     {"shadow", "shadow.png"},
                                     {"covering", "f_L.png"},
                                     {"regimes", "regimes.png"}}) {
    fs::remove(base / dir / picture);
    const Outcome o = run("plot " + (base / dir).string() + " --format png,pdf");
    EXPECT_EQ(o.status, 0) << dir << ": " << o.err;
    EXPECT_TRUE(fs::exists(base / dir / picture)) << dir;
    const fs::path pdf = (base / dir / picture).replace_extension(".pdf");
    EXPECT_EQ(slurp(pdf).rfind("%PDF-", 0), 0u) << pdf;
    // one line per picture: its files, then its caption
    EXPECT_NE(o.out.find("drew " + (base / dir / picture).string() + ", " + pdf.string() + ": "), std::string::npos)
        << o.out;
  }
  const Outcome tiff = run("plot " + (base / "run").string() + " --format png,tiff");
  EXPECT_EQ(tiff.status, 2);
  EXPECT_EQ(tiff.err, "rotleak.plot: --format = tiff: must be a comma list of png, pdf, svg\n");
  const Outcome none = run("plot " + scratch().string());
  EXPECT_EQ(none.status, 2);  // not a directory rotleak wrote: bad input, one line, no exception's type name
  EXPECT_NE(none.err.find("not a complete rotleak directory"), std::string::npos) << none.err;
  EXPECT_EQ(none.err.find("Error:"), std::string::npos) << none.err;
}

// rotleak fit redraws the pictures of a run it refits (they once kept the old fit): the picture
// after a refit differs, and refitting back to the first window draws the first picture again.
TEST(Cli, FitRedrawsThePicturesOfTheNewFit) {
  const fs::path scene = write_scene("small.toml", kSmall);
  const fs::path out = scratch() / "refit_plot";
  fs::remove_all(out);
  ASSERT_EQ(run("simulate " + scene.string() + " --out " + out.string() + " --plot").status, 0);
  const std::string first = slurp(out / "survival.png");
  ASSERT_FALSE(first.empty());
  const Outcome narrow = run("fit " + out.string() + " --set 'fit.kappa_window=[0, 150]'");
  ASSERT_EQ(narrow.status, 0) << narrow.err;
  EXPECT_NE(slurp(out / "survival.png"), first);
  ASSERT_EQ(run("fit " + out.string() + " --set 'fit.kappa_window=[0, 300]'").status, 0);
  EXPECT_EQ(slurp(out / "survival.png"), first);
}

// `--set` took every word after it, so `--set leak.omega=2/3 SCENE` said "scene is required".
TEST(Cli, SetTakesOneValueAndLeavesTheScene) {
  const fs::path scene = write_scene("small.toml", kSmall);
  const fs::path o = scratch() / "set_first";
  fs::remove_all(o);
  const Outcome r = run("simulate --set leak.omega=2/3 --set ensemble.particles=300 " + scene.string() + " --out " +
                        o.string() + " --no-progress");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(slurp(o / "summary.json"))["scene"]["leak"]["omega"], "2/3");
}

// `--out README.md` said "pass --force", and --force then refused: what --force cannot replace is said first.
TEST(Cli, WhatForceCannotReplaceIsSaidWithoutForce) {
  const fs::path scene = write_scene("small.toml", kSmall);
  const fs::path file = scratch() / "notes.md";
  std::ofstream(file) << "keep me\n";
  for (const char* force : {"", " --force"}) {
    const Outcome r = run("simulate " + scene.string() + " --out " + file.string() + force);
    EXPECT_EQ(r.status, 2);
    EXPECT_EQ(r.err.find("pass --force"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("choose another --out"), std::string::npos) << r.err;
  }
  EXPECT_EQ(slurp(file), "keep me\n");
}

// A second scan into a directory a scan is writing returned 0 with its points orphaned; a refit during a
// simulate --force was silently lost. Both take the directory's lock now (held here as a live run holds it).
TEST(Cli, ScanAndFitTakeTheDirectoryLock) {
  const fs::path scene = write_scene("small.toml", kSmall);
  const fs::path runs = scratch() / "lock_run";
  fs::remove_all(runs);
  ASSERT_EQ(run("simulate " + scene.string() + " --particles 300 --out " + runs.string() + " --no-progress").status, 0);
  const std::string before = slurp(runs / "summary.json");
  for (const char* name : {".lock_scan.lock", ".lock_run.lock"}) {
    const int fd = ::open((scratch() / name).c_str(), O_RDWR | O_CREAT, 0644);
    ASSERT_GE(fd, 0);
    ASSERT_EQ(::flock(fd, LOCK_EX), 0);
    const Outcome r = std::string(name) == ".lock_scan.lock"
                          ? run("scan " + scene.string() + " --over leak.omega=0 --set ensemble.particles=300 --out " +
                                (scratch() / "lock_scan").string() + " --no-progress")
                          : run("fit " + runs.string() + " --set fit.alpha_factor=5");
    EXPECT_EQ(r.status, 2) << name;
    EXPECT_NE(r.err.find("another rotleak run"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    ::close(fd);
    fs::remove(scratch() / name);
  }
  EXPECT_FALSE(fs::exists(scratch() / "lock_scan" / "table.csv"));
  EXPECT_EQ(slurp(runs / "summary.json"), before);
}

// Re-running a scan with other inputs replaced its points without --force (a 3*10^5-particle point by a
// 1000-particle one): refused, naming the point and the key that differs; --force replaces.
TEST(Cli, AScanRerunWithOtherInputsNeedsForce) {
  const fs::path scene = write_scene("small.toml", kSmall);
  const fs::path d = scratch() / "rerun_scan";
  fs::remove_all(d);
  const std::string base = "scan " + scene.string() + " --over leak.omega=0,1 --out " + d.string() + " --no-progress";
  ASSERT_EQ(run(base + " --set ensemble.particles=600").status, 0);
  const std::string table = slurp(d / "table.csv");
  const Outcome other = run(base + " --set ensemble.particles=300");
  EXPECT_EQ(other.status, 2);
  EXPECT_NE(other.err.find("ensemble.particles: 600 vs 300, there vs here"), std::string::npos) << other.err;
  EXPECT_EQ(slurp(d / "table.csv"), table);
  const Outcome same = run(base + " --set ensemble.particles=600");  // same inputs: resumed, nothing rerun
  EXPECT_EQ(same.status, 0) << same.err;
  const Outcome forced = run(base + " --set ensemble.particles=300 --force");
  EXPECT_EQ(forced.status, 0) << forced.err;
  EXPECT_NE(slurp(d / "table.csv"), table);
  // a damaged record (points.json not an object: once exit 1 at the first point written) records nothing:
  // the complete points are not replaced without --force, and with it the scan runs through
  std::ofstream(d / "points.json") << "[]\n";
  const Outcome damaged = run(base + " --set ensemble.particles=300");
  EXPECT_EQ(damaged.status, 2) << damaged.err;
  EXPECT_NE(damaged.err.find("not recorded in points.json"), std::string::npos) << damaged.err;
  EXPECT_EQ(run(base + " --set ensemble.particles=300 --force").status, 0);
}

// The lock file's own failure says why (it once said only "cannot create the lock file"): here the lock's
// name is taken by a directory.
TEST(Cli, ALockFileThatCannotBeMadeSaysWhy) {
  const fs::path scene = write_scene("small.toml", kSmall);
  fs::create_directories(scratch() / ".lockdir_run.lock");
  const Outcome r =
      run("simulate " + scene.string() + " --particles 100 --out " + (scratch() / "lockdir_run").string());
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("cannot create the lock file"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("(Is a directory)"), std::string::npos) << r.err;
  fs::remove(scratch() / ".lockdir_run.lock");
}

// scan --out on a read-only file system exited 1 with a raw "filesystem error", and simulate said "cannot
// create the lock file" without the reason. A parent that is a file fails the same calls (as root, where
// permissions do not): exit 2, one line, the reason from the system.
TEST(Cli, AnOutputThatCannotBeCreatedIsBadInputWithItsReason) {
  const fs::path scene = write_scene("small.toml", kSmall);
  const fs::path file = scratch() / "plain_file";
  std::ofstream(file) << "x\n";
  for (const std::string& cmd :
       {"scan " + scene.string() + " --over leak.omega=0 --set ensemble.particles=100 --out " + (file / "D").string(),
        "simulate " + scene.string() + " --particles 100 --out " + (file / "R").string()}) {
    const Outcome r = run(cmd + " --no-progress");
    EXPECT_EQ(r.status, 2) << cmd << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find("Not a directory"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("filesystem error"), std::string::npos) << r.err;
  }
}

// What the newcomer met in the reports: verify --tier mpfr:300 showed worst = 6.9e10 with "pass" and
// "bits 32/32" where nothing was stored; shadow --tiers mpfr:65536 failed to round the perimeter; the
// shadow table printed 17 digits; audit of a split scene exited 1 with internal wording; scan printed the
// raw CSV on stdout.
TEST(Cli, ReportsSayWhatTheyMeasured) {
  const Outcome v = run("verify --tier mpfr:300");
  ASSERT_EQ(v.status, 0) << v.err;
  std::istringstream lines(v.out);
  std::string line;
  bool seen = false;
  while (std::getline(lines, line))
    if (line.rfind("mpfr:300", 0) == 0) {
      seen = true;
      std::istringstream f(line);
      std::string tier, cases, horizon, reached, worst, decisions, bits;
      f >> tier >> cases >> horizon >> reached >> worst >> decisions >> bits;
      EXPECT_LE(std::stod(worst), 64.0) << line;
      EXPECT_EQ(bits, "none") << line;
    }
  EXPECT_TRUE(seen) << v.out;

  const std::string quick = std::string(rotleak::test::source_dir()) + "/data/scenes/quickstart.toml";
  const Outcome sh = run("shadow " + quick + " --particle 3 --tiers double,mpfr:65536 --collisions 40");
  EXPECT_EQ(sh.status, 0) << sh.err;
  std::istringstream rows(sh.out);
  while (std::getline(rows, line))
    if (line.rfind("double ", 0) == 0) {
      std::istringstream f(line);
      std::string tier, horizon, when;
      f >> tier >> horizon >> when;
      EXPECT_LE(when.size(), 8u) << line;  // six significant digits, not 17
    }

  const Outcome a = run("audit " + quick +
                        " --set run.splitting=true --set ensemble.sampling=mupo --set run.t_max=3000 "
                        "--set observe.collision_density={bins=10}");
  EXPECT_EQ(a.status, 2) << a.err;
  EXPECT_EQ(a.err.rfind("rotleak: error: run.splitting = true:", 0), 0u) << a.err;

  const fs::path scene = write_scene("small.toml", kSmall);
  const fs::path d = scratch() / "scan_stdout";
  fs::remove_all(d);
  const Outcome sc = run("scan " + scene.string() + " --over leak.omega=0,1 --set ensemble.particles=300 --out " +
                         d.string() + " --no-progress");
  ASSERT_EQ(sc.status, 0) << sc.err;
  EXPECT_EQ(sc.out.find("kappa_err"), std::string::npos) << sc.out;  // a table to read, not table.csv again
  EXPECT_NE(sc.out.find("regime"), std::string::npos) << sc.out;
}
