// CSV test vector files in tests/data (HOULE_TEST_DATA_DIR): comment lines start with '#', then a
// header row, then one row of comma-separated cells per vector.
#pragma once
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

struct TestVectors {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;  ///< text: sea_colours.csv names its seas
};

inline TestVectors read_test_vectors(const std::string& name) {
  std::ifstream f(std::string(HOULE_TEST_DATA_DIR) + "/" + name);
  EXPECT_TRUE(f.good()) << "cannot read " << name;
  TestVectors t;
  std::string line;
  while (std::getline(f, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) cells.push_back(cell);
    (t.header.empty() ? t.header : t.rows.emplace_back()) = std::move(cells);
  }
  return t;
}

inline std::vector<std::vector<double>> numeric_rows(const TestVectors& t) {
  std::vector<std::vector<double>> rows;
  for (const std::vector<std::string>& cells : t.rows) {
    std::vector<double>& row = rows.emplace_back();
    for (const std::string& c : cells) row.push_back(std::stod(c));
  }
  return rows;
}
