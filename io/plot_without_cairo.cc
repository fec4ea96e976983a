// The figures of io/plot.h in a build without Cairo (SURFREG_PLOTS
// OFF): every .png output is refused with one line, so the rest of the CLI
// works as usual.
#include <string>
#include <vector>

#include "measure/input_error.h"
#include "io/plot.h"

namespace surfreg {

bool PngFiguresBuilt() { return false; }

void RequirePngFigures(const std::string& label) {
  throw InputError(label + ": PNG figures need Cairo, and this surfreg was built without it "
                   "(cmake -DSURFREG_PLOTS=OFF, or libcairo2-dev missing)");
}

void WriteMapPng(const std::string&, const GridField&, const FigureText&, const MapStyle&,
                 const std::string& label) {
  RequirePngFigures(label);
}

void WriteChartPng(const std::string&, const std::vector<Series>&, const FigureText&,
                   const ChartStyle&, const std::string& label) {
  RequirePngFigures(label);
}

void WriteHistogramPng(const std::string&, const std::vector<Series>&, int, const FigureText&,
                       const ChartStyle&, const std::string& label) {
  RequirePngFigures(label);
}

}  // namespace surfreg
