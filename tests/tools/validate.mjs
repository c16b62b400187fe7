#!/usr/bin/env node
// Print the Khronos glTF-Validator's JSON report for one .gltf/.glb file.
// Usage: node validate.mjs FILE        (run `npm ci` in this directory first)
// Exit status: 0 when a report was produced (whatever it says), 2 when validation could not run.
// Side files (buffers, images) are read relative to FILE; every issue is reported (maxIssues 0)
// and the report has no timestamp, so equal files give equal reports.
import fs from 'node:fs';
import path from 'node:path';
import validator from 'gltf-validator';

const file = process.argv[2];
if (!file) {
  console.error('usage: node validate.mjs FILE');
  process.exit(2);
}
const dir = path.dirname(path.resolve(file));

try {
  const bytes = new Uint8Array(fs.readFileSync(file));
  const report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 0,
    writeTimestamp: false,
    externalResourceFunction: (uri) =>
      fs.promises
        .readFile(path.resolve(dir, decodeURIComponent(uri)))
        .then((data) => new Uint8Array(data)),
  });
  process.stdout.write(JSON.stringify(report, null, 2) + '\n');
} catch (error) {
  console.error(`validation failed to run on ${file}: ${error}`);
  process.exit(2);
}
