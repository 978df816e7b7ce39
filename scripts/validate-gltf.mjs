// Runs the Khronos glTF validator on .glb/.gltf files and on every tile of 3D Tiles tilesets
// (directories with a tileset.json). Prints each file's counts and messages; exits 1 on any error.
// Usage: node scripts/validate-gltf.mjs FILE_OR_TILESET...
import { readFileSync, readdirSync, statSync } from "node:fs";
import { join, dirname, resolve } from "node:path";
import { createRequire } from "node:module";

const require = createRequire(resolve("node_modules") + "/");
const validator = require("gltf-validator");

function files(path) {
  if (!statSync(path).isDirectory()) return [path];
  return readdirSync(path, { recursive: true })
    .filter((name) => /\.(glb|gltf)$/.test(name))
    .sort()
    .map((name) => join(path, name));
}

let errors = 0;
for (const arg of process.argv.slice(2)) {
  for (const file of files(arg)) {
    const report = await validator.validateBytes(new Uint8Array(readFileSync(file)), {
      uri: file,
      maxIssues: 0,
      externalResourceFunction: (uri) =>
        Promise.resolve(new Uint8Array(readFileSync(join(dirname(file), decodeURIComponent(uri))))),
    });
    const issues = report.issues;
    errors += issues.numErrors;
    console.log(`${file}: ${issues.numErrors} errors, ${issues.numWarnings} warnings, ` +
      `${issues.numInfos} infos, ${issues.numHints} hints`);
    const seen = new Map();
    for (const m of issues.messages) {
      const key = `${["error", "warning", "info", "hint"][m.severity]} ${m.code}: ${m.message}`;
      seen.set(key, (seen.get(key) || 0) + 1);
    }
    for (const [key, count] of seen) console.log(`  ${count} x ${key}`);
  }
}
process.exit(errors > 0 ? 1 : 0);
