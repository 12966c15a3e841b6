// integration/fusion360/ccomp-hook.cps run as Fusion 360 runs a post's onTerminate(), under
// node with stubs of the post functions it calls (getOutputPath, getProperty, execute, error,
// localize). The post's own `properties` object comes first (the hook is pasted after it) and
// getProperty() answers as Fusion does: the value set in the post dialog, else the default.
// The stub of execute() stands for Windows + WSL: it takes the command line given to wsl.exe
// apart as Windows does (double-quoted arguments), checks it is `--exec <command> ...`, maps
// /mnt/c/ to a folder standing for drive C: and runs the command here, returning its exit code.
//
//   CCOMP=build/src/ccomp node tests/cli/fusion360/fusion_hook_test.js
"use strict";
const assert = require("assert");
const child = require("child_process");
const fs = require("fs");
const os = require("os");
const path = require("path");
const vm = require("vm");

const source = path.resolve(__dirname, "..", "..", "..");
const hook = fs.readFileSync(path.join(source, "integration", "fusion360", "ccomp-hook.cps"), "utf8");
const drive = fs.mkdtempSync(path.join(os.tmpdir(), "ccomp-fusion-"));  // stands for C:\
const program = "G21 G90\nG0 X1 Y2\nG1 X3 F100\nM2\n";

function windowsArguments(line) {
  const args = [];
  const word = /"([^"]*)"|(\S+)/g;
  for (let m; (m = word.exec(line)) !== null;) args.push(m[1] !== undefined ? m[1] : m[2]);
  return args;
}

/** A post with its own property, and the hook pasted after its `properties = {...}`. */
function loadPost(context) {
  vm.createContext(context);
  vm.runInContext("properties = {writeMachine: {title: 'Write machine', type: 'boolean', value: true, scope: 'post'}};",
                  context);
  vm.runInContext(hook, context);
  return context;
}

function runHook(outputPath, dialog) {
  const calls = {execute: [], error: []};
  const context = {
    getOutputPath: () => outputPath,
    // Fusion: the value set in the post dialog, else the property's default.
    getProperty: (name) => {
      assert.ok(name in context.properties, "no post property " + name);
      return name in dialog ? dialog[name] : context.properties[name].value;
    },
    localize: (text) => text,
    error: (text) => calls.error.push(text),
    execute: (exe, line, hide, folder) => {
      calls.execute.push({exe, line});
      assert.strictEqual(exe, "C:\\Windows\\System32\\wsl.exe");
      const args = windowsArguments(line).map((a) => a.startsWith("/mnt/c/") ? path.join(drive, a.slice(7)) : a);
      assert.strictEqual(args[0], "--exec", line);
      const r = child.spawnSync(args[1], args.slice(2), {encoding: "utf8"});
      if (r.error) throw r.error;
      calls.stderr = r.stderr;
      return r.status;
    },
  };
  loadPost(context);
  vm.runInContext("onTerminate()", context);
  return calls;
}

const jobs = path.join(drive, "jobs", "part one");
fs.mkdirSync(jobs, {recursive: true});
const zero = path.join(source, "samples", "machines", "zero.yaml");
const tools = path.join(source, "samples", "tools.tbl");
const settings = {ccompCommand: process.env.CCOMP, ccompModel: zero, ccompTools: tools};

// The settings are post properties, added to the post's own, each with what Fusion's dialog shows.
const context = loadPost({});
assert.ok(context.properties.writeMachine, "the post's own property kept");
for (const name of ["ccompWsl", "ccompCommand", "ccompModel", "ccompTools", "ccompOptions"]) {
  const p = context.properties[name];
  assert.ok(p, name);
  assert.strictEqual(p.type, "string", name);
  assert.strictEqual(p.scope, "post", name);
  assert.strictEqual(p.group, "ccomp", name);
  assert.ok(p.title && p.description, name);
}
assert.strictEqual(context.properties.ccompWsl.value, "C:\\Windows\\System32\\wsl.exe");
assert.strictEqual(context.properties.ccompOptions.value, "");
// Older posts read plain values; the hook's reader takes a property's default then.
assert.strictEqual(vm.runInContext("ccompSetting('ccompModel')", context), "/etc/ccomp/machine.yaml");

// The wrapper's path conversion, as WSL mounts drives.
assert.strictEqual(context.ccompWslPath("C:\\jobs\\part one\\a.nc"), "/mnt/c/jobs/part one/a.nc");
assert.strictEqual(context.ccompWslPath("d:/x/b.tap"), "/mnt/d/x/b.tap");

// A program compensated in place, its backup kept.
fs.writeFileSync(path.join(jobs, "a.nc"), program);
let calls = runHook("C:\\jobs\\part one\\a.nc", settings);
assert.deepStrictEqual(calls.error, [], calls.stderr);
assert.strictEqual(calls.execute.length, 1);
const written = fs.readFileSync(path.join(jobs, "a.nc"), "utf8");
assert.ok(written.startsWith("(ccomp "), written);
assert.strictEqual(written.slice(written.indexOf("\n") + 1), program);
assert.strictEqual(fs.readFileSync(path.join(jobs, "a.nc.orig"), "utf8"), program);

// A refusal (X beyond the machine's 100 mm) stops the post with the exit code; no backup, file as posted.
const small = path.join(drive, "small.yaml");
fs.writeFileSync(small, "name: small\naxes: {X: {min: -100, max: 100}, Y: {min: -100, max: 100}}\n");
fs.writeFileSync(path.join(jobs, "far.nc"), "G21 G90\nG0 X150\nM2\n");
calls = runHook("C:\\jobs\\part one\\far.nc", Object.assign({}, settings, {ccompModel: small, ccompTools: ""}));
assert.strictEqual(calls.error.length, 1);
assert.ok(calls.error[0].includes("(exit 7)"), calls.error[0]);
assert.ok(calls.stderr.includes("refused: axis X would go to 150"), calls.stderr);
assert.ok(!calls.execute[0].line.includes("--tool-table"), calls.execute[0].line);
assert.strictEqual(fs.readFileSync(path.join(jobs, "far.nc"), "utf8"), "G21 G90\nG0 X150\nM2\n");
assert.ok(!fs.existsSync(path.join(jobs, "far.nc.orig")));

// Any ccomp option through the "more options" property: the full sample HMC has thermal
// terms, refused without their sensors (the missing one named); with them the program is
// compensated.
const hmc = path.join(source, "samples", "machines", "hmc-xyzb.yaml");
const part = "G21 G90 G54\nT1 M6\nG43 H1\nG0 X10 Y20 Z50\nG1 X60 F300\nG1 Y80\nM2\n";
fs.writeFileSync(path.join(jobs, "hmc.nc"), part);
calls = runHook("C:\\jobs\\part one\\hmc.nc", Object.assign({}, settings, {ccompModel: hmc}));
assert.strictEqual(calls.error.length, 1, "refused without the sensors");
assert.ok(/\(exit [1-9]\d*\)/.test(calls.error[0]), calls.error[0]);
assert.ok(/sensor.*bed|bed.*sensor/.test(calls.stderr), calls.stderr);
// The hint is the whole command, tool table included, to run in a WSL terminal.
assert.ok(calls.error[0].includes(" -m " + hmc + " --tool-table " + tools), calls.error[0]);
assert.strictEqual(fs.readFileSync(path.join(jobs, "hmc.nc"), "utf8"), part);
const sensors = "--sensor bed=21 --sensor column=20.5 --sensor spindle=30 --time 3600";
calls = runHook("C:\\jobs\\part one\\hmc.nc",
                Object.assign({}, settings, {ccompModel: hmc, ccompOptions: sensors + " --tolerance \"0.002\""}));
assert.deepStrictEqual(calls.error, [], calls.stderr);
assert.ok(calls.execute[0].line.endsWith(" --in-place " + sensors + " --tolerance \"0.002\""), calls.execute[0].line);
const compensated = fs.readFileSync(path.join(jobs, "hmc.nc"), "utf8");
const header = compensated.split("\n")[0];
assert.ok(header.startsWith("(ccomp ") && / at 2 um\b/.test(header), header);
assert.notStrictEqual(compensated.slice(compensated.indexOf("\n") + 1), part, "the thermal model moved points");
// The same as ccomp run by hand with those options.
const byHand = child.spawnSync(process.env.CCOMP, [path.join(jobs, "hmc.nc.orig"), "-m", hmc, "--tool-table", tools,
  "-o", "-"].concat(sensors.split(" ")).concat(["--tolerance", "0.002"]), {encoding: "utf8"});
assert.strictEqual(byHand.status, 0, byHand.stderr);
assert.strictEqual(compensated.slice(compensated.indexOf("\n")), byHand.stdout.slice(byHand.stdout.indexOf("\n")));
// A bad option reaches ccomp and is refused as usage (exit 2), the program as posted.
fs.writeFileSync(path.join(jobs, "b.nc"), program);
calls = runHook("C:\\jobs\\part one\\b.nc", Object.assign({}, settings, {ccompOptions: "--dialect klingon"}));
assert.ok(calls.error.length === 1 && calls.error[0].includes("(exit 2)"), calls.error.join());  // usage
assert.ok(calls.error[0].endsWith(" --dialect klingon"), calls.error[0]);
assert.strictEqual(fs.readFileSync(path.join(jobs, "b.nc"), "utf8"), program);

fs.rmSync(drive, {recursive: true, force: true});
console.log("fusion hook: all checks passed");
