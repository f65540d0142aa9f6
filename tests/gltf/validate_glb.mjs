// node validate_glb.mjs PREFIX PATH...
//
// Runs the Khronos glTF-Validator (npm gltf-validator, pinned by
// package-lock.json beside this file and installed by install_validator.sh
// into PREFIX/node_modules) on every .glb given or found (not
// recursively) in a given folder, and prints each file's messages.
// Exit 0 only if at least one GLB was validated and no file has an error,
// a warning, or an info/hint that is not in kAcceptedInfos below (with the
// reason it is acceptable); 1 otherwise; 2 on bad usage.
import { readdirSync, readFileSync, statSync } from 'node:fs';
import { createRequire } from 'node:module';
import { join, resolve } from 'node:path';

// Infos and hints that are acceptable, each with why. Errors and warnings
// never are. None so far: every GLB the suite writes validates with no
// message at all.
const kAcceptedInfos = {};

const [prefix, ...paths] = process.argv.slice(2);
if (!prefix || paths.length === 0) {
  console.error('usage: node validate_glb.mjs PREFIX FILE.glb|FOLDER...');
  process.exit(2);
}
const validator = createRequire(join(resolve(prefix), 'package.json'))('gltf-validator');

const files = [];
for (const p of paths) {
  if (statSync(p).isDirectory()) {
    for (const name of readdirSync(p).sort()) {
      if (name.toLowerCase().endsWith('.glb')) files.push(join(p, name));
    }
  } else {
    files.push(p);
  }
}
if (files.length === 0) {
  console.error('validate_glb: no .glb found in ' + paths.join(' '));
  process.exit(1);
}

const kSeverity = ['error', 'warning', 'info', 'hint'];
let failed = 0;
for (const file of files) {
  const report = await validator.validateBytes(new Uint8Array(readFileSync(file)), {
    uri: file,
    format: 'glb',
    maxIssues: 0,
    writeTimestamp: false,
  });
  const bad = [];
  for (const m of report.issues.messages) {
    const accepted = m.severity >= 2 && m.code in kAcceptedInfos;
    const line = `${kSeverity[m.severity]} ${m.code} at ${m.pointer ?? ''}: ${m.message}` +
      (accepted ? ` (accepted: ${kAcceptedInfos[m.code]})` : '');
    if (!accepted) bad.push(line);
    console.log(`${file}: ${line}`);
  }
  const i = report.issues;
  console.log(`${file}: ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos, ` +
    `${i.numHints} hints -> ${bad.length ? 'FAIL' : 'ok'}`);
  if (bad.length) ++failed;
}
console.log(`validate_glb: ${files.length - failed} of ${files.length} GLBs pass`);
process.exit(failed ? 1 : 0);
