// Validates one glTF 2.0 file (.glb or .gltf) with the Khronos glTF-Validator (npm
// gltf-validator) and prints its report as JSON on stdout. Exit status: 0 when the validator ran
// (whatever it found; the caller reads issues.numErrors), 2 on a usage or reading problem.
// Usage: node tests/tools/validate-gltf.js FILE
'use strict';
const fs = require('fs');
const path = require('path');

let validator;
try {
  validator = require('gltf-validator');
} catch (e) {
  process.stderr.write('validate-gltf: the npm package gltf-validator is not installed in ' +
                       __dirname + ' (run scripts/install-test-tools.sh): ' + e.message + '\n');
  process.exit(2);
}

const file = process.argv[2];
if (!file) {
  process.stderr.write('usage: node validate-gltf.js FILE\n');
  process.exit(2);
}
let bytes;
try {
  bytes = new Uint8Array(fs.readFileSync(file));
} catch (e) {
  process.stderr.write('validate-gltf: cannot read ' + file + ': ' + e.message + '\n');
  process.exit(2);
}
validator
    .validateBytes(bytes, {
      uri: path.basename(file),
      maxIssues: 0,
      writeTimestamp: false,
      externalResourceFunction: (uri) =>
          Promise.reject(new Error('external resource ' + uri + ' not allowed in a .glb test')),
    })
    .then((report) => {
      process.stdout.write(JSON.stringify(report, null, 2) + '\n');
    })
    .catch((e) => {
      process.stderr.write('validate-gltf: ' + file + ': ' + e + '\n');
      process.exit(2);
    });
