// SPDX-License-Identifier: Apache-2.0
#pragma once
// `stgf eval` on files (DESIGN §3.8, §4): scene by scene when the files allow it, so that memory
// holds one scene of each file, not the files; otherwise whole, as always.
//
// Scene by scene needs every file grouped by scene (each scene's rows contiguous) and in one scene
// order: the measurements' (or, without them, the first estimate file's), which the truth file and
// every estimate file follow; without measurements, the truth file may hold other scenes between
// them. The benchmarks' files and `stgf run`'s estimates are so. The numbers are those of evaluate()
// on the whole files, bit for bit (SceneScores).
//
// Otherwise — files in other orders, or a problem that evaluate() decides from the whole files (a
// missing estimate, an estimate or a measurement without truth, ...) — the files are read whole and
// evaluate() scores them or reports the problem, exactly as before, with the memory that takes. A bad
// row (an InputError of a reader) is reported at once; with several bad rows in several files, which
// one comes first can differ from reading the files whole, one after the other.

#include <string>
#include <vector>

#include "stgf/io/evaluation.hpp"

namespace stgf {

// evaluate() on the files at these paths (`measurements` empty: none). `read_whole_because`, when
// given, says why the files were read whole ("" when they were read scene by scene).
Evaluation evaluate_files(const std::string& truth, const std::vector<std::string>& estimates,
                          const std::string& measurements, const ScoringStart& start,
                          std::string* read_whole_because = nullptr);

}  // namespace stgf
