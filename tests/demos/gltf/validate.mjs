// Validates glTF files with the Khronos glTF validator and prints one line per file:
//   <file>: <errors> errors, <warnings> warnings, <infos> infos, <hints> hints
// followed by every error and warning message. Exits 1 when any file has an error (or
// cannot be read), 0 otherwise.
//   node validate.mjs scene.glb [more.glb ...]
import { readFile } from 'node:fs/promises';
import validator from 'gltf-validator';

let failed = false;
for (const file of process.argv.slice(2)) {
  try {
    const bytes = new Uint8Array(await readFile(file));
    const report = await validator.validateBytes(bytes, { maxIssues: 0, writeTimestamp: false });
    const s = report.issues;
    console.log(`${file}: ${s.numErrors} errors, ${s.numWarnings} warnings, ${s.numInfos} infos, ${s.numHints} hints`);
    for (const m of s.messages)
      if (m.severity <= 2) console.log(`  ${["error", "warning", "info"][m.severity]} ${m.code} ${m.pointer ?? ''}: ${m.message}`);
    if (s.numErrors > 0) failed = true;
  } catch (e) {
    console.log(`${file}: cannot validate: ${e.message ?? e}`);
    failed = true;
  }
}
process.exit(failed ? 1 : 0);
