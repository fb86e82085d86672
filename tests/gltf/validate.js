// Khronos' glTF-Validator on one file: `node validate.js FILE` prints its report as JSON.
// The validator is the npm package scripts/setup.sh installs under $FFD_NPM_PREFIX
// (default ~/.cache/ffdtool/npm); external buffers and images resolve beside FILE.
"use strict";
const fs = require("fs");
const os = require("os");
const path = require("path");

const prefix = process.env.FFD_NPM_PREFIX || path.join(os.homedir(), ".cache", "ffdtool", "npm");
const validator = require(path.join(prefix, "node_modules", "gltf-validator"));
const file = process.argv[2];
const folder = path.dirname(path.resolve(file));

const external = (uri) =>
  new Promise((resolve, reject) =>
    fs.readFile(path.resolve(folder, decodeURIComponent(uri)), (err, data) =>
      err ? reject(err.toString()) : resolve(new Uint8Array(data))));

validator
  .validateBytes(new Uint8Array(fs.readFileSync(file)), {
    uri: path.basename(file),
    maxIssues: 0,
    externalResourceFunction: external,
  })
  .then((report) => console.log(JSON.stringify(report)))
  .catch((error) => {
    console.error(file + ": " + String(error));
    process.exit(1);
  });
