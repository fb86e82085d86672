// Khronos' glTF-Validator. `node validate.js FILE` prints FILE's report as JSON.
// `node validate.js --serve` reads one path a line on stdin and prints each file's report
// as one line of JSON, in order ({"error": "..."} for a file it cannot validate), so that
// a test validating many files starts node once (about 0.2 s a start) instead of per file.
// The validator is the npm package scripts/setup.sh installs under $FFD_NPM_PREFIX
// (default ~/.cache/ffdtool/npm); external buffers and images resolve beside FILE.
"use strict";
const fs = require("fs");
const os = require("os");
const path = require("path");
const readline = require("readline");

const prefix = process.env.FFD_NPM_PREFIX || path.join(os.homedir(), ".cache", "ffdtool", "npm");
const validator = require(path.join(prefix, "node_modules", "gltf-validator"));

function validate(file) {
  const folder = path.dirname(path.resolve(file));
  const external = (uri) =>
    new Promise((resolve, reject) =>
      fs.readFile(path.resolve(folder, decodeURIComponent(uri)), (err, data) =>
        err ? reject(err.toString()) : resolve(new Uint8Array(data))));
  return validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
    uri: path.basename(file),
    maxIssues: 0,
    externalResourceFunction: external,
  });
}

if (process.argv[2] === "--serve") {
  // One file at a time, so that the reports come out in the order the paths came in.
  let queue = Promise.resolve();
  readline.createInterface({ input: process.stdin }).on("line", (file) => {
    queue = queue
      .then(() => validate(file))
      .then((report) => process.stdout.write(JSON.stringify(report) + "\n"))
      .catch((error) => process.stdout.write(JSON.stringify({ error: file + ": " + String(error) }) + "\n"));
  });
} else {
  const file = process.argv[2];
  validate(file)
    .then((report) => console.log(JSON.stringify(report)))
    .catch((error) => {
      console.error(file + ": " + String(error));
      process.exit(1);
    });
}
