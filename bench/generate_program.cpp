// Writes a 3-axis finishing program of N lines: a raster of short G1 moves over a wavy
// surface, as a CAM system posts a ball-end finishing pass (4-decimal coordinates). Past
// 4M lines (400 mm of rows, within the sample HMC's Y travel) the tool lifts, goes back to
// the first row and finishes the surface again: a 10M-line program runs on that machine.
//   ccomp_bench_generate 1000000 finishing-1M.ngc
#include <cmath>
#include <cstdio>
#include <cstdlib>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s LINES OUTPUT\n", argv[0]);
    return 2;
  }
  const long lines = std::atol(argv[1]);
  std::FILE* out = std::fopen(argv[2], "w");
  if (!out) return 6;
  std::fputs("%\n(synthetic 3-axis finishing pass)\nG21 G17 G90 G94 G40 G49 G80 G54\n", out);
  std::fputs("T1 M6\nG43 H1\nS12000 M3\nG0 X0 Y0 Z5\nG1 Z0 F1500\n", out);
  const long per_row = 2000, rows_per_pass = 2000;
  for (long i = 0; i < lines; ++i) {
    const long row = i / per_row % rows_per_pass, col = i % per_row;
    const double x = static_cast<double>(row % 2 == 0 ? col : per_row - 1 - col) * 0.05;
    const double y = static_cast<double>(row) * 0.2;
    const double z = -1.0 + 0.5 * std::sin(x * 0.1) * std::cos(y * 0.07);
    if (i > 0 && i % (per_row * rows_per_pass) == 0) std::fputs("G0 Z5\nG0 X0 Y0\nG1 Z0\n", out);  // the next pass
    std::fprintf(out, "G1 X%.4f Y%.4f Z%.4f\n", x, y, z);
  }
  std::fputs("G0 Z50\nM5\nM30\n%\n", out);
  return std::fclose(out) == 0 ? 0 : 6;
}
