// A matrix written by dump.patch (int n, int nnz, colptr[n + 1], rowind[nnz], double values[nnz],
// compressed columns), and a millisecond clock: what lu.cpp, elu.cpp and chol.cpp share.
#pragma once
#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

struct DumpedMatrix {
  int n = 0, nnz = 0;
  std::vector<int> p, i;
  std::vector<double> x;
};

inline DumpedMatrix read_dumped(const char* path) {
  DumpedMatrix m;
  std::FILE* f = std::fopen(path, "rb");
  if (!f) throw std::runtime_error(std::string("cannot open ") + path);
  bool ok = std::fread(&m.n, 4, 1, f) == 1 && std::fread(&m.nnz, 4, 1, f) == 1;
  if (ok) {
    m.p.resize(m.n + 1);
    m.i.resize(m.nnz);
    m.x.resize(m.nnz);
    ok = std::fread(m.p.data(), 4, m.n + 1, f) == std::size_t(m.n + 1) &&
         std::fread(m.i.data(), 4, m.nnz, f) == std::size_t(m.nnz) &&
         std::fread(m.x.data(), 8, m.nnz, f) == std::size_t(m.nnz);
  }
  std::fclose(f);
  if (!ok) throw std::runtime_error(std::string("truncated dump ") + path);
  return m;
}

inline double now_ms() {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
