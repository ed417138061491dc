// Checks .glb files with the Khronos glTF validator (npm gltf-validator).
// Usage: node validate.mjs FILE.glb...   Exit status 0 when every file has 0 errors; the
// errors (and warnings) are printed one per line as "FILE: SEVERITY CODE POINTER: MESSAGE".
import { readFile } from 'node:fs/promises';
import validator from 'gltf-validator';

const files = process.argv.slice(2);
if (files.length === 0) {
  console.error('usage: node validate.mjs FILE.glb...');
  process.exit(2);
}
const severities = ['error', 'warning', 'info', 'hint'];
let errors = 0;
for (const file of files) {
  const bytes = new Uint8Array(await readFile(file));
  const report = await validator.validateBytes(bytes, {
    uri: file,
    maxIssues: 100,
    externalResourceFunction: (uri) => Promise.reject(new Error(`external resource ${uri}`)),
  });
  const issues = report.issues;
  errors += issues.numErrors;
  for (const m of issues.messages) {
    if (m.severity <= 1) {
      console.log(`${file}: ${severities[m.severity]} ${m.code} ${m.pointer ?? ''}: ${m.message}`);
    }
  }
  console.log(`${file}: ${issues.numErrors} errors, ${issues.numWarnings} warnings`);
}
process.exit(errors === 0 ? 0 : 1);
