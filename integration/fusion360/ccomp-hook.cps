/*
  Fusion 360 (Autodesk CAM) post-processor hook: compensate the posted program with ccomp.
  Paste into your post (.cps) and merge onTerminate() with the post's own, if it has one.
  Fusion calls onTerminate() after the output file is closed; getOutputPath() names it.
  ccomp rewrites it in place (keeping a .orig backup) and a refusal stops with its message.

  ccomp is built for Linux (there is no Windows build). Fusion runs on Windows or macOS, so:
  - Windows: build ccomp inside WSL (Windows Subsystem for Linux) with tools/build.sh and
    install it there (e.g. /usr/local/bin/ccomp). The hook runs it through wsl.exe with the
    posted file's path as WSL sees it (C:\jobs\part.nc -> /mnt/c/jobs/part.nc). The model
    and the tool table are Linux paths inside WSL.
  - Otherwise (no WSL): leave this hook out and compensate where the program goes next, on
    a Linux host: the LinuxCNC [FILTER] entry or the batch script (docs/integration.md).
  tests/cli/fusion360/ runs this hook under node with stubs of Fusion's post functions.
*/
var ccompWsl = "C:\\Windows\\System32\\wsl.exe";  // runs the Linux command below
var ccompCommand = "/usr/local/bin/ccomp";          // inside WSL: a full Linux path
var ccompModel = "/etc/ccomp/machine.yaml";         // inside WSL
var ccompTools = "/etc/ccomp/tool.tbl";             // inside WSL; "" when programs use no G43 H

/** A Windows path as WSL mounts it: C:\dir\part.nc -> /mnt/c/dir/part.nc. */
function ccompWslPath(path) {
  var drive = /^([A-Za-z]):[\\\/](.*)$/.exec(path);
  if (!drive) {
    return path.replace(/\\/g, "/");
  }
  return "/mnt/" + drive[1].toLowerCase() + "/" + drive[2].replace(/\\/g, "/");
}

/** One argument for the Windows command line wsl.exe parses (paths hold no '"'). */
function ccompQuote(argument) {
  return "\"" + argument + "\"";
}

function onTerminate() {
  var program = getOutputPath();
  // wsl.exe --exec runs the command without a shell: each quoted argument reaches ccomp as is.
  var args = "--exec " + ccompQuote(ccompCommand) + " " + ccompQuote(ccompWslPath(program)) +
    " -m " + ccompQuote(ccompModel) + (ccompTools ? " --tool-table " + ccompQuote(ccompTools) : "") + " --in-place";
  var code = execute(ccompWsl, args, true, "");
  if (code != 0) {
    error(localize("ccomp refused to compensate " + program + " (exit " + code + "); the uncompensated program is unchanged. " +
      "Run the command in a WSL terminal to see its message: " + ccompCommand + " " + ccompWslPath(program) + " -m " + ccompModel));
  }
}
