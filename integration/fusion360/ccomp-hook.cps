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
  Its settings are the post properties below (the post dialog's "ccomp" group): the model,
  the tool table and any other ccomp options (--sensor, --dialect, --work-offset ...).
  tests/cli/fusion360/ runs this hook under node with stubs of Fusion's post functions.
*/
// The hook's settings are post properties: Fusion shows them in the post dialog (group
// "ccomp") and keeps them with the NC program, so each machine's post process can name its
// model and its ccomp options. Paste this after the post's own `properties = {...}`: the
// entries are added to it.
var ccompProperties = {
  ccompWsl: {title: "ccomp: wsl.exe", description: "The Windows program that runs the Linux command (WSL).",
    group: "ccomp", type: "string", value: "C:\\Windows\\System32\\wsl.exe", scope: "post"},
  ccompCommand: {title: "ccomp: command", description: "ccomp inside WSL: a full Linux path.",
    group: "ccomp", type: "string", value: "/usr/local/bin/ccomp", scope: "post"},
  ccompModel: {title: "ccomp: machine model", description: "The machine model (YAML), a Linux path inside WSL.",
    group: "ccomp", type: "string", value: "/etc/ccomp/machine.yaml", scope: "post"},
  ccompTools: {title: "ccomp: tool table", description: "The tool table, a Linux path inside WSL; empty when programs use no G43 H.",
    group: "ccomp", type: "string", value: "/etc/ccomp/tool.tbl", scope: "post"},
  ccompOptions: {title: "ccomp: more options",
    description: "Any other ccomp options, as on a command line (double quotes around a value with blanks): " +
      "--sensor bed=21 --sensor spindle=30 --dialect fanuc --work-offset G54=X0,Y0,Z-400 --tolerance 0.001",
    group: "ccomp", type: "string", value: "", scope: "post"}
};
if (typeof properties == "undefined") {
  properties = {};
}
for (var ccompName in ccompProperties) {
  properties[ccompName] = ccompProperties[ccompName];
}

/** A property's value as the user set it (getProperty() in today's post API; a plain value, or
    its default, in older ones). */
function ccompSetting(name) {
  if (typeof getProperty == "function") {
    return getProperty(name);
  }
  var p = properties[name];
  return (p !== null && typeof p == "object") ? p.value : p;
}

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

/** An argument as a shell in a WSL terminal reads it (for the message to the user). */
function ccompShellQuote(argument) {
  return /^[A-Za-z0-9_@%+=:,.\/-]+$/.test(argument) ? argument : "'" + argument.replace(/'/g, "'\\''") + "'";
}

function onTerminate() {
  var program = getOutputPath();
  var command = ccompSetting("ccompCommand");
  var model = ccompSetting("ccompModel");
  var tools = ccompSetting("ccompTools");
  var options = ccompSetting("ccompOptions") || "";
  // wsl.exe --exec runs the command without a shell: each argument reaches ccomp as Windows
  // splits the line (blanks, double quotes); the options are passed on as the user wrote them.
  var args = "--exec " + ccompQuote(command) + " " + ccompQuote(ccompWslPath(program)) +
    " -m " + ccompQuote(model) + (tools ? " --tool-table " + ccompQuote(tools) : "") + " --in-place" +
    (options ? " " + options : "");
  var code = execute(ccompSetting("ccompWsl"), args, true, "");
  if (code != 0) {
    var hint = [command, ccompWslPath(program), "-m", model].concat(tools ? ["--tool-table", tools] : [])
      .map(ccompShellQuote).join(" ") + (options ? " " + options : "");
    error(localize("ccomp refused to compensate " + program + " (exit " + code + "); the uncompensated program is unchanged. " +
      "Run the command in a WSL terminal to see its message: " + hint));
  }
}
