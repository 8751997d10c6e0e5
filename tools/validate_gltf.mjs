// Validate a glTF/GLB file with the Khronos glTF validator and print its JSON report.
// Usage: node tools/validate_gltf.mjs FILE
// Exit status: 0 when the report has no errors, 1 when it has errors, 2 when
// the file could not be read or validated at all.
import { readFile } from 'node:fs/promises';
import { basename } from 'node:path';
import validator from 'gltf-validator';

const file = process.argv[2];
if (!file) {
  console.error('usage: node validate_gltf.mjs FILE');
  process.exit(2);
}
try {
  const bytes = new Uint8Array(await readFile(file));
  const report = await validator.validateBytes(bytes, { uri: basename(file), maxIssues: 100 });
  console.log(JSON.stringify(report, null, 2));
  process.exit(report.issues.numErrors > 0 ? 1 : 0);
} catch (error) {
  console.error(`validate_gltf: ${file}: ${error}`);
  process.exit(2);
}
