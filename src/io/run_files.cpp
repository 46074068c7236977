/* run_files.cpp - the files of a run before any work: their folders, whether they can be written,
 * that no file has two roles; and the default paths of the partial output and the checkpoint. */
#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sys/stat.h>

#include "io/run_impl.h"

namespace gran_run {

namespace {

/* mkdir -p of the folder holding `path` */
int make_parent(const std::string &path) {
  size_t s = path.find_last_of('/');
  if (s == std::string::npos || s == 0) return GRAN_SUCCESS;
  std::string dir = path.substr(0, s);
  for (size_t i = 1; i <= dir.size(); i++) {
    if (i == dir.size() || dir[i] == '/') {
      std::string d = dir.substr(0, i);
      if (mkdir(d.c_str(), 0777) != 0 && errno != EEXIST)
        return GRAN_ERROR(GRAN_ERR_IO, "cannot create folder '%s' for '%s': %s", d.c_str(), path.c_str(),
                          std::strerror(errno));
    }
  }
  return GRAN_SUCCESS;
}

/* Writability check before any work: create PATH.tmp, then remove it. */
int check_writable(const std::string &path, const char *what) {
  GRAN_CALL(make_parent(path));
  std::string tmp = path + ".tmp";
  FILE *f = std::fopen(tmp.c_str(), "wb");
  if (!f) return GRAN_ERROR(GRAN_ERR_IO, "%s '%s' is not writable: %s", what, tmp.c_str(), std::strerror(errno));
  std::fclose(f);
  std::remove(tmp.c_str());
  struct stat sb;
  if (stat(path.c_str(), &sb) == 0 && S_ISDIR(sb.st_mode))
    return GRAN_ERROR(GRAN_ERR_IO, "%s '%s' is a folder", what, path.c_str());
  return GRAN_SUCCESS;
}

/* Identity of a file: "dev:inode" when it exists, else the real path of its folder plus its name
 * (two spellings of one file, links and ./ prefixes compare equal). */
std::string file_identity(const std::string &path) {
  struct stat sb;
  if (stat(path.c_str(), &sb) == 0) return "inode " + std::to_string((unsigned long long)sb.st_dev) + ":" +
                                           std::to_string((unsigned long long)sb.st_ino);
  size_t sl = path.find_last_of('/');
  std::string dir = sl == std::string::npos ? "." : (sl == 0 ? "/" : path.substr(0, sl));
  std::string base = sl == std::string::npos ? path : path.substr(sl + 1);
  char buf[PATH_MAX];
  if (realpath(dir.c_str(), buf)) return std::string("path ") + buf + "/" + base;
  return "path " + path;
}

/* Refuse two roles for one file, by identity: every file a run reads or writes (the scene file,
 * the checkpoint it resumes from or writes, the output and the partial output, the sidecars the
 * engine writes beside them, and the .tmp of each written file). */
int check_distinct(const Run &r, const std::string &scene_file) {
  struct Role {
    std::string what, path;
  };
  std::unique_ptr<gran_engine> eng; /* for its sidecars: no state is built */
  GRAN_CALL(gran_engine_create_(r.s, eng));
  std::vector<Role> roles = {{"scene file", scene_file}};
  auto written = [&](const std::string &what, const std::string &path) {
    if (path.empty()) return;
    roles.push_back({what, path});
    roles.push_back({"temporary file of the " + what, path + ".tmp"});
  };
  written("checkpoint", r.ckpt);
  const std::string part = gran_partial_path_(r.out);
  written("output", r.out);
  written("partial output", part);
  for (const auto &p : eng->sidecars(r.out)) written("sidecar of the output", p);
  for (const auto &p : eng->sidecars(part)) written("sidecar of the partial output", p);
  for (size_t a = 0; a < roles.size(); a++)
    for (size_t b = a + 1; b < roles.size(); b++) {
      if (roles[a].path.empty() || roles[b].path.empty()) continue;
      if (file_identity(roles[a].path) == file_identity(roles[b].path))
        return GRAN_ERROR(GRAN_ERR_ARG, "the %s '%s' and the %s '%s' are the same file", roles[a].what.c_str(),
                          roles[a].path.c_str(), roles[b].what.c_str(), roles[b].path.c_str());
    }
  return GRAN_SUCCESS;
}

}  // namespace

/* The files of a run: distinct, and writable (before any work). */
int check_files(Run &r, const std::string &scene_file) {
  GRAN_CALL(check_distinct(r, scene_file));
  GRAN_CALL(check_writable(r.out, "output file"));
  if (!r.ckpt.empty()) GRAN_CALL(check_writable(r.ckpt, "checkpoint file"));
  return GRAN_SUCCESS;
}

}  // namespace gran_run

std::string gran_partial_path_(const std::string &out) {
  const size_t n = out.size();
  if (n > 3 && out.compare(n - 3, 3, ".h5") == 0) return out.substr(0, n - 3) + ".partial.h5";
  return out + ".partial.h5";
}

std::string gran_run_checkpoint_path_(const gran_scene *s, const char *output, const char *checkpoint) {
  if (checkpoint) return checkpoint;
  /* the default checkpoint (OUTPUT.ckpt) follows -o; a path the scene names stays */
  if (output && s->checkpoint_path == s->output_path + ".ckpt") return std::string(output) + ".ckpt";
  return s->checkpoint_path;
}

std::string gran_file_identity_(const std::string &path) { return gran_run::file_identity(path); }
int gran_make_parent_(const std::string &path) { return gran_run::make_parent(path); }
