#include "gpgpu/compact.h"

#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <stdexcept>

namespace gpgpu {

std::vector<float> Compacted::read_records() const {
  if (count == 0) return {};
  std::vector<float> v = records.read();
  v.resize(size_t(count) * size_t(channels(records.format())));
  return v;
}

std::vector<uint32_t> Compacted::read_source() const {
  if (count == 0) return {};
  std::vector<uint32_t> v = source.read_u32();
  v.resize(size_t(count));
  return v;
}

namespace {

/// The most pyramid levels of an input of the GPU's largest size (along both axes): one gather
/// program serves every size (a program per level count cost each new count its compilation and
/// first draw).
int max_levels(Gpu& gpu, int fanout) {
  int per_axis = 0;
  for (int n = gpu.info().max_texture_size; n > 1; n = (n + fanout - 1) / fanout) ++per_axis;
  return std::max(2 * per_axis, 1);
}

/// `cut`: the predicate is "channel 0 <= u_cut" (compact_at_most) instead of "channel 0 > 0".
Program& build_program(Gpu& gpu, bool from_predicate, int fanout, bool cut) {
  return gpu.program("histopyramid_build.frag", {{"FROM_PREDICATE", from_predicate ? "1" : "0"},
                                                 {"FANOUT", std::to_string(fanout)},
                                                 {"PREDICATE_CUT", from_predicate && cut ? "1" : "0"}});
}

Program& gather_program(Gpu& gpu, int fanout, bool cut) {
  return gpu.program("histopyramid_gather.frag", {{"MAX_LEVELS", std::to_string(max_levels(gpu, fanout))},
                                                  {"FANOUT", std::to_string(fanout)},
                                                  {"PREDICATE_CUT", cut ? "1" : "0"}});
}

void check_fanout(int fanout) {
  if (fanout != 4 && fanout != 16)
    throw std::invalid_argument(fmt::format("compact: fan-out {} is not 4 or 16", fanout));
}

}  // namespace

void compile_compact(Gpu& gpu, int fanout, bool cut) {
  check_fanout(fanout);
  build_program(gpu, true, fanout, cut);
  build_program(gpu, false, fanout, cut);
  gather_program(gpu, fanout, cut);
}

namespace {

/// compact() (no cut) or compact_at_most() (the predicate is channel 0 <= *cut).
Compacted compact_impl(Gpu& gpu, const Texture& predicate, const Texture& records, int fanout,
                       std::optional<float> cut) {
  check_fanout(fanout);
  if (predicate.width() != records.width() || predicate.height() != records.height())
    throw std::invalid_argument(fmt::format("compact: predicate {}x{} and records {}x{} differ", predicate.width(),
                                            predicate.height(), records.width(), records.height()));
  if (is_integer(records.format()) || is_integer(predicate.format()))
    throw std::invalid_argument("compact: predicate and records must be float or R8 textures");

  // Build: reduce along rows by `fanout` until one column, then along the column until 1x1.
  std::vector<PooledTexture> levels;
  std::vector<std::pair<int, int>> axes;
  const Texture* in = &predicate;
  do {
    const bool along_x = in->width() > 1;
    const int w = along_x ? (in->width() + fanout - 1) / fanout : 1;
    const int h = along_x ? in->height() : (in->height() + fanout - 1) / fanout;
    Program& p = build_program(gpu, levels.empty(), fanout, cut.has_value());
    if (levels.empty() && cut) p.set("u_cut", *cut);
    p.set("u_src_size", in->width(), in->height());
    p.set("u_axis", along_x ? 1 : 0, along_x ? 0 : 1);
    PooledTexture next = gpu.acquire(w, h, Format::R32UI);
    const Input inputs[] = {{"u_src", in}};
    Texture* outputs[] = {next.get()};
    gpu.run("histopyramid_build", p, inputs, outputs);
    axes.emplace_back(along_x ? 1 : 0, along_x ? 0 : 1);
    levels.push_back(std::move(next));
    in = levels.back().get();
  } while (in->width() > 1 || in->height() > 1);

  Compacted out;
  out.levels = static_cast<int>(levels.size());
  out.count = levels.back()->read_u32()[0];
  for (size_t i = 0; i < levels.size(); ++i) gpu.dump(fmt::format("histopyramid_level{}", i), *levels[i]);

  int max_size = gpu.info().max_texture_size;
  out.layout = layout_for(out.count, max_size);
  out.records =
      Texture(out.layout.width, out.layout.height, records.format() == Format::R8 ? Format::R32F : records.format());
  out.source = Texture(out.layout.width, out.layout.height, Format::R32UI);
  if (out.count == 0) return out;

  const int most = max_levels(gpu, fanout);
  if (out.levels > most || most > 16)
    throw std::length_error(fmt::format("compact: {} pyramid levels, at most {}", out.levels, std::min(most, 16)));
  const int units_needed = most + 1;
  if (units_needed > gpu.info().max_texture_units)
    throw std::length_error(fmt::format("compact: {} pyramid levels need {} texture units, the GPU has {}", most,
                                        units_needed, gpu.info().max_texture_units));
  Program& g = gather_program(gpu, fanout, cut.has_value());
  if (cut) g.set("u_cut", *cut);
  std::vector<Input> inputs{{"u_pred", &predicate}, {"u_records", &records}};
  for (int i = 0; i + 1 < most; ++i) {
    // The 1x1 top level is where the descent starts (p = 0); its count was read above, the shader
    // never samples it, nor the levels past it (bound to it so that every sampler has an integer texture).
    const size_t l = std::min(size_t(i), levels.size() - 1);
    inputs.push_back({fmt::format("u_levels[{}]", i), levels[l].get()});
  }
  for (int i = 0; i < most; ++i) {
    const auto axis = size_t(i) < axes.size() ? axes[size_t(i)] : std::pair{0, 0};
    g.set(fmt::format("u_level_axis[{}]", i), axis.first, axis.second);
  }
  g.set("u_num_levels", out.levels);
  g.set("u_out_width", out.layout.width);
  g.set("u_count", static_cast<unsigned>(out.count));
  Texture* outputs[] = {&out.records, &out.source};
  gpu.run("histopyramid_gather", g, inputs, outputs);
  gpu.dump("compacted_records", out.records);
  return out;
}

}  // namespace

Compacted compact(Gpu& gpu, const Texture& predicate, const Texture& records, int fanout) {
  return compact_impl(gpu, predicate, records, fanout, std::nullopt);
}

Compacted compact_at_most(Gpu& gpu, const Texture& values, float cut, const Texture& records, int fanout) {
  if (values.format() == Format::R8) throw std::invalid_argument("compact_at_most: the values must be a float texture");
  return compact_impl(gpu, values, records, fanout, cut);
}

}  // namespace gpgpu
