// The tools' one command-line parser: what it accepts, and the message for each malformed command line.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tread_wear/cli/command_line.h"

using tread_wear::CommandLine;

namespace {

struct Parsed {
  CommandLine line;
  bool ok = false;
  std::string error;
};

Parsed parse(std::vector<const char*> args, std::size_t max_positional = 0) {
  args.insert(args.begin(), "tool");
  Parsed p;
  p.ok = p.line.parse(static_cast<int>(args.size()), args.data(), {"params", "rate-hz", "seed"}, {"quiet"}, &p.error,
                      max_positional);
  return p;
}

}  // namespace

TEST(CommandLine, OptionsSwitchesAndPositionals) {
  const Parsed p = parse({"--params", "a.yaml", "in.csv", "--quiet"}, 1);
  ASSERT_TRUE(p.ok) << p.error;
  EXPECT_EQ(p.line.get("params"), "a.yaml");
  EXPECT_TRUE(p.line.has("quiet"));
  EXPECT_FALSE(p.line.has("seed"));
  EXPECT_EQ(p.line.get("seed", "7"), "7");
  ASSERT_EQ(p.line.positional().size(), 1u);
  EXPECT_EQ(p.line.positional()[0], "in.csv");
  EXPECT_FALSE(p.line.help());
  EXPECT_TRUE(parse({"-h"}).line.help());
  EXPECT_TRUE(parse({"--help"}).line.help());
}

TEST(CommandLine, MalformedCommandLinesNameTheArgument) {
  EXPECT_EQ(parse({"--colour", "red"}).error, "unknown option '--colour'");
  EXPECT_EQ(parse({"--params"}).error, "option '--params' needs a value");
  EXPECT_EQ(parse({"--params", "a", "--params", "b"}).error, "option '--params' given twice");
  EXPECT_EQ(parse({"--quiet", "--quiet"}).error, "option '--quiet' given twice");
  EXPECT_EQ(parse({"extra.csv"}).error, "unexpected argument 'extra.csv'");
  EXPECT_EQ(parse({"a.csv", "b.csv"}, 1).error, "unexpected argument 'b.csv'");
}

TEST(CommandLine, NumbersAndIntegers) {
  std::string error;
  const Parsed p = parse({"--rate-hz", "50.5", "--seed", "12"});
  double rate_hz = 0.0;
  int seed = 0;
  EXPECT_TRUE(p.line.number("rate-hz", &rate_hz, &error));
  EXPECT_TRUE(p.line.integer("seed", &seed, &error));
  EXPECT_DOUBLE_EQ(rate_hz, 50.5);
  EXPECT_EQ(seed, 12);

  double untouched = 3.0;  // absent options leave the default as it is
  EXPECT_TRUE(parse({}).line.number("rate-hz", &untouched, &error));
  EXPECT_EQ(untouched, 3.0);

  for (const char* bad : {"abc", "nan", "inf", "5x", ""}) {
    EXPECT_FALSE(parse({"--rate-hz", bad}).line.number("rate-hz", &rate_hz, &error)) << bad;
    EXPECT_EQ(error, std::string("--rate-hz must be a number, not '") + bad + "'");
  }
  for (const char* bad : {"1.5", "x", "99999999999"}) {
    EXPECT_FALSE(parse({"--seed", bad}).line.integer("seed", &seed, &error)) << bad;
    EXPECT_EQ(error, std::string("--seed must be an integer, not '") + bad + "'");
  }
}

TEST(CommandLine, SplitList) {
  EXPECT_EQ(tread_wear::splitList("a,b,,c"), (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_TRUE(tread_wear::splitList("").empty());
}

TEST(CommandLine, GridSize) {
  int nx = 0, ns = 0;
  EXPECT_TRUE(tread_wear::parseGridSize("3200x16", &nx, &ns));
  EXPECT_EQ(nx, 3200);
  EXPECT_EQ(ns, 16);
  EXPECT_TRUE(tread_wear::parseGridSize("400,24", &nx, &ns));
  EXPECT_EQ(nx, 400);
  EXPECT_EQ(ns, 24);
  for (const char* bad : {"400", "400x", "x16", "400x16x2", "400x16 ", "a,b", "400;16"})
    EXPECT_FALSE(tread_wear::parseGridSize(bad, &nx, &ns)) << bad;
}
