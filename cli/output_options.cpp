#include "output_options.hpp"

#include "whole_number.hpp"

#include <CLI/CLI.hpp>

void add_output_options(CLI::App& app, OutputOptions& output, bool streamed) {
  app.add_option("--compression", output.encode.compression,
                 "how the output is compressed. PNG: fast[:FILTER] (ISA-L's igzip; the default, fast:up: files about "
                 "0.65x the size of libvips') or LEVEL[:FILTER[:STRATEGY]], zlib LEVEL 0-9, FILTER none, sub, "
                 "up, avg, paeth or adaptive (not with fast), zlib STRATEGY default, filtered, huffman, rle or "
                 "fixed (9:adaptive for the smallest files). EXR: "
                 "none, rle, zips, zip, piz, pxr24, b44, b44a, dwaa[:LEVEL], dwab[:LEVEL] (default piz, lossless; "
                 "dwa and b44 are lossy). TIFF: none, lzw, zip[:1-9] (zip alone: level 6), packbits, "
                 "jpeg[:QUALITY] (default zip:1)");
  app.add_option("--quality", output.encode.quality, "JPEG quality, 1 to 100 (default 90)")
      ->check(whole_number(1, 100));
  app.add_flag("--half", output.encode.half,
               "EXR: 16-bit half-float samples (half the bytes; 11 bits of precision, plenty for 8- and 10-bit "
               "inputs) instead of 32-bit floats. Default: half for 8-bit and half inputs, 32-bit float for "
               "16-bit and float inputs");
  app.add_flag("--float", output.encode.full_float, "EXR: 32-bit float samples, whatever the input");
  app.add_option("--tile-size", output.encode.tile,
                 "TIFF and EXR: write tiles of N x N pixels (a multiple of 16, e.g. 512) instead of rows: what "
                 "viewers of very large images read fastest (TIFF over 4 GB becomes BigTIFF by itself)")
      ->check(whole_number(16, 65536));
  if (!streamed) return;
  app.add_flag("--no-stream", output.no_stream,
               "hold the whole output in memory and write it at the end, instead of writing it by bands of rows "
               "as they are rendered (same file, bit for bit; more memory)");
}
