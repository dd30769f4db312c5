// caustica bench: refraction (deferred against forward), compare (caustic methods side by side), photons (the paper's table) and accuracy
// (speed against accuracy against the ground truth). Run by hand; results go into docs/.
// This file has the help and picks the benchmark: load, refraction, compare and photons are in
// bench_frames.cpp, accuracy, stability and convergence in bench_accuracy.cpp, bench_stability.cpp
// and bench_convergence.cpp, what they share in bench_common.h.
#include <iostream>

#include "bench_common.h"
#include "cli.h"
#include "core/suggest.h"

namespace caustica::cli {

int cmd_bench(Args& args) {
  const char* help =
      "usage: caustica bench refraction [--scene FILE]... [--sphere-detail N]... [--size WxH] [--frames N] [--csv FILE]\n"
      "       caustica bench compare --graphs A,B[,...] [--scene FILE] [--size WxH] [--frames N] [--set NAME=VALUE]... [--csv FILE]\n"
      "       caustica bench photons [--scene FILE] [--grids 256,512,...] [--frames N] [--regular-max G] [--out DIR]\n"
      "       caustica bench stability [--grid G] [--out DIR] ...\n"
      "       caustica bench load --scene FILE [--runs N]\n"
      "       caustica bench accuracy --out DIR [--scenes A,B] [--graphs G,H,...] [--grids 256,512,...] [--frames N]\n"
      "                               [--regular-max G] [--caustic-size N] [--size WxH] [--reference-photons N] [--blur SIGMA]\n"
      "       caustica bench convergence --out DIR [--scene NAME] [--methods A,B] [--seconds S | --frames N] ...\n"
      "       caustica bench accuracy|stability ... --list-cells | --cell K|auto --out DIR [--reference-cache DIR]\n"
      "       caustica bench merge DIR... --out OUT\n\n"
      "cells (docs/cluster.md): --list-cells prints the sweep's cells, one a line from 0 (scene or case, graph, grid or\n"
      "distances); --cell K runs cell K alone (auto: K from SLURM_ARRAY_TASK_ID or JOB_COMPLETION_INDEX) and writes\n"
      "DIR/cell_K.csv; --reference-cache DIR keeps the photon references there, as shards in a folder named by the\n"
      "reference's key (scene identity, photons, map size, seed), for the cells that need them again. bench merge joins\n"
      "every cell of one sweep into the results one process writes, and names the cells missing.\n\n"
      "accuracy: speed against accuracy. For every scene (bundled names or files; default sphere_plane,bunny_plane) x\n"
      "caustic graph x effective photon grid (default 256..4096; the regular map only up to --regular-max, 4096): the\n"
      "median GPU time of the caustic pass and of the frame, and the error of the caustic map against the photon\n"
      "reference (--reference-photons, default 1e8) after a matched blur; and for every refraction graph x distance\n"
      "(dv, dv_dn, search; a graph that traces exact paths by default, with its own): the refraction passes' time and\n"
      "error against the ray-traced reference. Writes DIR/results.csv, DIR/speed_accuracy.png (error against time,\n"
      "log-log, python3-matplotlib), DIR/README.md and each scene's reference map. Default graphs: the five caustic\n"
      "graphs, the max-error one also with converge_test=same_texel (the paper's test), the default one also with\n"
      "distance=dv_dn (the paper's estimate), the adaptive hybrid with distance=search and as\n"
      "it is, caustics_raytraced, refraction_forward, refraction_deferred, refraction_raytraced, refraction_hybrid (exact\n"
      "paths by the device's tracer, --tracer; a graph --tracer ray_query refuses is skipped, with a note). A graph is NAME or\n"
      "NAME:PARAM=VALUE[:PARAM=VALUE...]. The chart is drawn with matplotlib by /usr/bin/python3 (python3 on PATH where\n"
      "there is none), or by the interpreter that CAUSTICA_PYTHON names; one that cannot import matplotlib stops the\n"
      "benchmark before it starts.\n\n"
      "       caustica bench stability [--cases A,B] [--grid G] [--caustic-size N] [--frames N] [--reference-photons N] [--out DIR]\n"
      "                                [--validate]\n\n"
      "stability: where each caustic method breaks. Every case (ball lens; bunny with the light moving; n = 2.4; grazing\n"
      "light; torus; stacked refractors; a refractor smaller than the start grid's spacing; one filling the light's view;\n"
      "the light close to it; a point light close to it; a bulb in a glass globe, every caustic view of it; two\n"
      "lights' caustics overlapping; a thin film at grazing light; a clear coat over a rough base; n = 1; no refractor)\n"
      "x every method (the hybrid also without coverage seeding, and the\n"
      "exact-path ladder: the adaptive hybrid graph with the search and with exact re-traces, and the exact tracer, by\n"
      "the device's tracer or --tracer's) at one grid\n"
      "(default 2048): error, energy ratio and shape error against the photon reference (default 2e7), NaN/Inf count,\n"
      "photons, caustic-pass time, the change after moving the light by 1e-4 (and the reference's own change), and the\n"
      "flicker along a light path against the reference's own. DIR/stability.csv and DIR/README.md. --frames 0 renders\n"
      "one untimed frame per method (caustic ms then nan in the CSV). --cases runs some of\n"
      "the cases, named by their scenes: sphere_plane, bunny_plane, high_index, grazing_light, torus, three_refractors,\n"
      "tiny_refractor, filling_refractor, close_light, close_point_light, glass_lamp, overlapping_caustics,\n"
      "grazing_film, coat_over_rough, index_one, no_refractor.\n\n"
      "       caustica bench convergence --out DIR [--scene NAME] [--graph NAME] [--methods A,B] [--seconds S | --frames N]\n"
      "                                  [--grid G] [--caustic-size N] [--size WxH] [--reference-photons N | --reference FILE.exr]\n"
      "                                  [--blur SIGMA]\n\n"
      "convergence: error against wall time while a progressive graph accumulates, as the viewer does when left still.\n"
      "For every method (values of the graph's `distance`; default dv_dn,search,hybrid,ray_query, those that need ray\n"
      "queries skipped on a device without them), from a fresh start after one frame that compiles its pipelines: the\n"
      "mean caustic map against the photon reference (default 1e8 photons, or a map given with --reference, e.g. one\n"
      "that bench accuracy wrote) after frames 1 to 8 and then about four per doubling, for --seconds (default 30) or\n"
      "--frames. Scene default glass_bunny, graph caustics_progressive (its grid and caustic_size unless given), size\n"
      "1280x720. Writes DIR/convergence.csv, DIR/convergence.md (time to 0.10 and 0.05), DIR/convergence.png (error\n"
      "against seconds, log-log) and, where DIR holds bench accuracy's results.csv, speed_accuracy.png again with the\n"
      "convergence panel beside its own.\n\n"
      "photons: the paper's table on a scene (default the bunny): photons processed by the regular, hierarchical and\n"
      "adaptive (max level, max error, hybrid) caustic maps for each effective grid, and the caustic pass's GPU time;\n"
      "DIR/photons.csv has columns grid, method, processed, gpu_ms. --regular-max skips the regular map above a grid.\n\n"
      "compare: caustic methods side by side, e.g. a user pass against the built-in it replaces: the graphs of --graphs\n"
      "(names or files; the first is the one the others are compared with) on one scene (--scene, default sphere_plane),\n"
      "one process, frames interleaved after two warm-up frames of each: the median GPU time of each graph's caustic\n"
      "passes (built-in, or user passes that write the image 'caustics') and of its frame, and their ratios to the\n"
      "first's. --set NAME=VALUE sets a parameter in every graph; --csv FILE writes the table.\n\n"
      "refraction: deferred against forward refraction on the same scenes (default: the bundled ball lens and bunny),\n"
      "one run, frames interleaved, after two warm-up frames: median GPU time of the refraction passes\n"
      "(refractor_buffers + the refraction pass) and of the whole frame. --sphere-detail renders the ball-lens scene\n"
      "with its sphere tessellated into N slices (triangle count alone varies).\n\n"
      "load: loading a scene or model file, median over --runs (default 5): the host's part (parsing, decoding the\n"
      "textures its materials use, normals, d_N) and the device's (buffers, textures with their mip chains), and how\n"
      "many of the file's images were decoded. tools/make_load_asset.py writes a textured 100k-triangle test model.\n\n"
      "merge: joins the cells of a bench accuracy or bench stability sweep (each written by --cell K --out DIR as\n"
      "DIR/cell_K.csv) into what one process writes: results.csv, README.md and speed_accuracy.png, or\n"
      "stability.csv and README.md, in OUT. Every cell of one sweep must be there once; otherwise nothing is\n"
      "written and the missing cells are named by index (resubmit those), as are duplicates and cells of\n"
      "another sweep. Exit 0, 1 for such cells, 2 for a usage error (docs/cluster.md).\n\n"
      "The graph parameters: bench compare runs each graph at rest, as render does (each parameter's first\n"
      "\"while_still\" value unless --set sets it; --moving: as declared); bench accuracy, stability and\n"
      "convergence chart each method as its graph declares it (convergence sets `distance` to each method).\n";
  if (args.wants_help()) {
    std::cout << help;
    for (const char* benchmark : {"refraction", "compare", "photons", "load"})
      std::cout << "\n" << benchmark << " options:\n" << bench::frames_flags_help(benchmark);
    std::cout << "\naccuracy options:\n"
              << bench::accuracy_flags_help() << "\nstability options:\n"
              << bench::stability_flags_help() << "\nconvergence options:\n"
              << bench::convergence_flags_help() << "\nmerge options:\n"
              << bench::merge_flags_help();
    return 0;
  }
  if (args.done())
    throw UsageError(
        "bench needs a benchmark name: refraction, compare, photons, accuracy, stability, convergence or load (or merge); see caustica "
        "bench "
        "--help");
  std::string what = args.take();
  if (what == "refraction") return bench::cmd_bench_refraction(args);
  if (what == "compare") return bench::cmd_bench_compare(args);
  if (what == "photons") return bench::cmd_bench_photons(args);
  if (what == "accuracy") return bench::cmd_bench_accuracy(args);
  if (what == "stability") return bench::cmd_bench_stability(args);
  if (what == "load") return bench::cmd_bench_load(args);
  if (what == "convergence") return bench::cmd_bench_convergence(args);
  if (what == "merge") return bench::cmd_bench_merge(args);
  throw UsageError("bench " + what + ": unknown benchmark" +
                   did_you_mean(what, {"refraction", "compare", "photons", "accuracy", "stability", "convergence", "load", "merge"}));
}

}  // namespace caustica::cli
