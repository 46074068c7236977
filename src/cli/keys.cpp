/* keys.cpp - `granary keys [ENGINE] [--format text|markdown]`: the scene keys of each engine, as
 * the engines declare them (src/<engine>/scene_<engine>.cpp, the core's shared keys in
 * src/io/scene.cpp). The markdown form (one table per engine: key | type | default | bounds |
 * unit | meaning | C field) is the generated key reference of the manual. */
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "cli.h"
#include "io/engine.h"

namespace {

/* The engine's keys with the shared ones, grouped by table: the top level first, then each table
 * after the table that declares it (depth first), a table's shared keys before the engine's. */
std::vector<const gran_scene_key *> ordered(const gran_engine_entry &e) {
  size_t nc = 0;
  const gran_scene_key *common = gran_scene_common_keys_(&nc);
  std::vector<const gran_scene_key *> all;
  for (size_t i = 0; i < nc; i++) all.push_back(&common[i]);
  for (size_t i = 0; i < e.nkeys; i++) all.push_back(&e.keys[i]);
  std::vector<std::string> tables;
  std::vector<const gran_scene_key *> out;
  std::vector<bool> done(all.size(), false);
  auto visit = [&](auto &&self, const std::string &t) -> void {
    for (size_t i = 0; i < all.size(); i++)
      if (!done[i] && t == all[i]->table) done[i] = true, out.push_back(all[i]);
    for (size_t i = 0; i < all.size(); i++)
      if (t == all[i]->table && std::strstr(all[i]->type, "table"))
        self(self, t.empty() ? std::string(all[i]->name) : t + "." + all[i]->name);
  };
  visit(visit, "");
  for (size_t i = 0; i < all.size(); i++)
    if (!done[i]) out.push_back(all[i]); /* tables not declared as keys (none today) */
  return out;
}

std::string full_name(const gran_scene_key &k) { return std::string(k.table) + (k.table[0] ? "." : "") + k.name; }

/* a markdown table cell: | escaped, empty as "-" */
std::string cell(const char *s, bool code = false) {
  if (!s || !s[0]) return "-";
  std::string o;
  for (const char *p = s; *p; p++) {
    if (*p == '|') o += '\\';
    o += *p;
  }
  return code ? "`" + o + "`" : o;
}

void print_markdown(const gran_engine_entry &e) {
  std::printf("## %s: `[engine] type = \"%s\"`\n\n", e.name, e.type);
  std::printf("| key | type | default | bounds | unit | meaning | C field |\n");
  std::printf("| --- | --- | --- | --- | --- | --- | --- |\n");
  for (const gran_scene_key *k : ordered(e))
    std::printf("| %s | %s | %s | %s | %s | %s | %s |\n", cell(full_name(*k).c_str(), true).c_str(), cell(k->type).c_str(),
                cell(k->def, true).c_str(), cell(k->bounds).c_str(), cell(k->unit).c_str(), cell(k->meaning).c_str(),
                cell(k->field, true).c_str());
  std::printf("\n");
}

void print_text(const gran_engine_entry &e) {
  std::printf("%s: [engine] type = \"%s\"\n", e.name, e.type);
  for (const gran_scene_key *k : ordered(e)) {
    char head[128];
    std::snprintf(head, sizeof head, "  %-36s %-24s", full_name(*k).c_str(), k->type);
    std::string line = head;
    if (k->def[0]) line += std::string("  default ") + k->def;
    if (k->bounds[0]) line += std::string("  bounds ") + k->bounds;
    if (k->unit[0]) line += std::string("  [") + k->unit + "]";
    while (!line.empty() && line.back() == ' ') line.pop_back();
    std::printf("%s\n  %-36s %s (%s)\n", line.c_str(), "", k->meaning, k->field);
  }
  std::printf("\n");
}

int usage(FILE *f, int rc) {
  size_t n = 0;
  const gran_engine_entry *all = gran_engine_entries_(&n);
  std::string types;
  for (size_t i = 0; i < n; i++) types += (i ? " | " : "") + std::string(all[i].type);
  std::fprintf(f,
               "usage: granary keys [ENGINE] [--format text|markdown]\n"
               "  the scene keys of ENGINE (%s; all engines when not given): table.key, TOML type,\n"
               "  default, bounds, unit, meaning and the C field it fills\n",
               types.c_str());
  return rc;
}

}  // namespace

int cli_keys(int argc, char **argv) {
  const char *engine = nullptr;
  bool markdown = false;
  for (int i = 1; i < argc; i++) {
    if (!std::strcmp(argv[i], "--help") || !std::strcmp(argv[i], "-h")) return usage(stdout, 0);
    if (!std::strcmp(argv[i], "--format") || !std::strncmp(argv[i], "--format=", 9)) {
      const char *f = argv[i][8] == '=' ? argv[i] + 9 : (i + 1 < argc ? argv[++i] : "");
      if (!std::strcmp(f, "markdown")) markdown = true;
      else if (!std::strcmp(f, "text")) markdown = false;
      else {
        std::fprintf(stderr, "granary keys: --format must be text or markdown, got '%s'\n", f);
        return 2;
      }
    } else if (argv[i][0] == '-' || engine) {
      std::fprintf(stderr, "granary keys: unexpected argument '%s'\n", argv[i]);
      return usage(stderr, 2);
    } else {
      engine = argv[i];
    }
  }
  size_t n = 0;
  const gran_engine_entry *all = gran_engine_entries_(&n);
  if (engine && !gran_engine_find_(engine)) {
    std::fprintf(stderr, "granary keys: unknown engine '%s'\n", engine);
    return usage(stderr, 2);
  }
  size_t nc = 0;
  const gran_scene_key *common = gran_scene_common_keys_(&nc);
  std::string bad = gran_scene_schema_problems_(common, nc);
  for (size_t i = 0; i < n; i++) bad += gran_scene_schema_problems_(all[i].keys, all[i].nkeys);
  if (!bad.empty()) {
    std::fprintf(stderr, "granary keys: the schema is inconsistent: %s\n", bad.c_str());
    return 1;
  }
  for (size_t i = 0; i < n; i++) {
    if (engine && std::strcmp(engine, all[i].type)) continue;
    if (markdown) print_markdown(all[i]);
    else print_text(all[i]);
  }
  return 0;
}
