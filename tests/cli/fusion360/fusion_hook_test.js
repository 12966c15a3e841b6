// integration/fusion360/ccomp-hook.cps run as Fusion 360 runs a post's onTerminate(), under
// node with stubs of the post functions it calls (getOutputPath, execute, error, localize).
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

function runHook(outputPath, settings) {
  const calls = {execute: [], error: []};
  const context = {
    getOutputPath: () => outputPath,
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
  vm.createContext(context);
  vm.runInContext(hook, context);
  Object.assign(context, settings);  // what the user sets at the top of the hook
  vm.runInContext("onTerminate()", context);
  return calls;
}

const jobs = path.join(drive, "jobs", "part one");
fs.mkdirSync(jobs, {recursive: true});
const zero = path.join(source, "samples", "machines", "zero.yaml");
const settings = {ccompCommand: process.env.CCOMP, ccompModel: zero, ccompTools: path.join(source, "samples", "tools.tbl")};

// The wrapper's path conversion, as WSL mounts drives.
const context = {};
vm.createContext(context);
vm.runInContext(hook, context);
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

fs.rmSync(drive, {recursive: true, force: true});
console.log("fusion hook: all checks passed");
