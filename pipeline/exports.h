// The solver exports of a run's Bézier elements, shared by volts-extract, volts-fit and
// volts-tet2hex: the files of extract.exports (bezier.vtu, bezier.bext + bezier.k, bezier.json,
// bezier.msh, scaled_jacobian_histogram.png), written beside --output or in the work directory.
#pragma once

#include "core/stage_file.h"
#include "extract/extract.h"
#include "stage_main.h"

namespace volts::pipeline {

/// Checks extract.exports against `degree` (before any work: a bad list costs nothing).
void check_exports(const StageContext& ctx, int degree, const std::string& degree_key);

/// The .vtu path of the run: --output, else bezier.vtu in the work directory; the other exports
/// are written beside it with its stem (bezier.bext, ...).
std::string vtu_path(const StageContext& ctx);

/// Writes the exports of `r` that extract.exports asks for other than the .vtu (bezier.bext +
/// bezier.k, bezier.json, bezier.msh, scaled_jacobian_histogram.png); returns them by kind. For a
/// route with a .vtu of its own (volts-tet2hex).
core::Json write_solver_exports(const StageContext& ctx, const extract::Result& r);

/// Writes the exports of `r` and logs them; returns the report figures of extract::report_figures
/// plus "output" (the .vtu, if written) and "outputs" (every file by kind).
core::Json write_exports(const StageContext& ctx, const extract::Result& r);

}  // namespace volts::pipeline
