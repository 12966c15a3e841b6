/*
  Fusion 360 (Autodesk CAM) post-processor hook: compensate the posted program with ccomp.
  Paste into your post (.cps) and merge onTerminate() with the post's own, if it has one.
  Fusion calls onTerminate() after the output file is closed; getOutputPath() names it.
  ccomp rewrites it in place (keeping a .orig backup) and a refusal stops with its message.
*/
var ccompPath = "C:\\Program Files\\ccomp\\ccomp.exe";  // or "/usr/local/bin/ccomp"
var ccompModel = "C:\\ccomp\\machine.yaml";
var ccompTools = "C:\\ccomp\\tool.tbl";

function onTerminate() {
  var program = getOutputPath();
  var args = "\"" + program + "\" -m \"" + ccompModel + "\" --tool-table \"" + ccompTools + "\" --in-place";
  var code = execute(ccompPath, args, false, "");
  if (code != 0) {
    error(localize("ccomp refused to compensate " + program + " (exit " + code + "); the uncompensated program is unchanged."));
  }
}
