#!/usr/bin/env node
// Validates one glTF 2.0 file (.glb or .gltf) with the Khronos glTF validator and prints its
// report as JSON on stdout. Exit code: 0 when the report has no errors, 1 when it has some,
// 2 when the file cannot be read.
"use strict";
const fs = require("fs");
const path = require("path");
const validator = require("gltf-validator");

async function main() {
  const file = process.argv[2];
  if (!file) {
    console.error("usage: node validate.js FILE.glb|FILE.gltf");
    process.exit(2);
  }
  let bytes;
  try {
    bytes = new Uint8Array(fs.readFileSync(file));
  } catch (e) {
    console.error(`error: cannot read ${file}: ${e.message}`);
    process.exit(2);
  }
  const dir = path.dirname(file);
  const report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 100,
    externalResourceFunction: (uri) =>
      new Promise((resolve, reject) => {
        fs.readFile(path.resolve(dir, decodeURIComponent(uri)), (err, data) => (err ? reject(err.toString()) : resolve(new Uint8Array(data))));
      }),
  });
  console.log(JSON.stringify(report, null, 2));
  process.exit(report.issues.numErrors > 0 ? 1 : 0);
}

main().catch((e) => {
  console.error(`error: ${e}`);
  process.exit(2);
});
