#!/usr/bin/env python3
"""Unit test of scripts/function_census.py on small C++ texts whose functions,
names and lengths are known by reading them."""
import io
import os
import sys
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts"))
import function_census as fc  # noqa: E402

SOURCE = r'''#include <map>
#define BODY { return 1; }
namespace ppp {
namespace {
const std::map<int, int> kTable = {{1, 2}, {3, 4}};
int helper(int a) {
  const char* s = "}{ \" }";
  char c = '}';
  int big = 1'000'000;
  /* } */ // {
  return a + big + c + s[0];
}
}  // namespace

class Foo : public Bar<int> {
 public:
  Foo(int a) : a_(a), b_{a, 2} {
    auto f = [](int x) {
      return x;
    };
    a_ = f(a_);
  }
  int get() const { return a_; }
  Foo& operator=(const Foo& o) = default;
  bool operator()(int x) const {
    return x > 0;
  }
 private:
  enum class Kind { kA, kB };
  int a_;
  int b_[2];
};

template <typename T = int>
T Foo::twice(T x) noexcept -> T {
  const char* raw = R"x(a "}" {)x";
  struct Local {
    int f() { return 1; }
  };
  return x + x;
}
}  // namespace ppp

extern "C" {
int c_entry(void) {
  return 0;
}
}
'''


class FunctionsInTest(unittest.TestCase):
    def setUp(self):
        found = fc.functions_in("x.cpp", SOURCE)
        self.by_name = {f.name: f for f in found}

    def test_finds_each_body_once(self):
        self.assertEqual(sorted(self.by_name), sorted([
            "ppp::helper", "ppp::Foo::Foo", "ppp::Foo::get",
            "ppp::Foo::operator()", "ppp::Foo::twice", "c_entry"]))

    def test_lengths_from_name_line_to_closing_brace(self):
        self.assertEqual(self.by_name["ppp::helper"].length, 7)  # lines 6..12
        self.assertEqual(self.by_name["ppp::helper"].line, 6)
        self.assertEqual(self.by_name["ppp::Foo::Foo"].length, 6)   # lambda inside counts
        self.assertEqual(self.by_name["ppp::Foo::get"].length, 1)
        self.assertEqual(self.by_name["ppp::Foo::operator()"].length, 3)
        self.assertEqual(self.by_name["ppp::Foo::twice"].length, 7)  # local class inside
        self.assertEqual(self.by_name["c_entry"].length, 3)


class ReportTest(unittest.TestCase):
    def test_counts_and_lists(self):
        found = [fc.Function("a.cpp", 1, "f", 61), fc.Function("a.cpp", 90, "g", 101),
                 fc.Function("b.cpp", 5, "h", 10)]
        out = io.StringIO()
        fc.report(found, top=2, over=None, out=out)
        text = out.getvalue()
        self.assertIn("functions: 3\n", text)
        self.assertIn("over 60 lines: 2 (66.7 %)\n", text)
        self.assertIn("over 100 lines: 1 (33.3 %)\n", text)
        self.assertIn("longest 2:\n  101  g  a.cpp:90\n   61  f  a.cpp:1\n", text)
        out = io.StringIO()
        fc.report(found, top=15, over=5, out=out)
        self.assertIn("over 5 lines (3):\n", out.getvalue())


if __name__ == "__main__":
    unittest.main()
