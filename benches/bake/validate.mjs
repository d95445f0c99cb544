// Runs the Khronos glTF validator (npm gltf-validator) on a .glb or .gltf and prints its
// report's counts and messages as one JSON object.
// Usage: node benches/bake/validate.mjs FILE   (with gltf-validator resolvable from the cwd,
// or NODE_PATH set to a node_modules folder that has it)
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { join } from 'node:path';

const require = createRequire(join(process.env.NODE_MODULES_DIR || process.cwd(), 'x.js'));
const validator = require('gltf-validator');
const file = process.argv[2];
const report = await validator.validateBytes(new Uint8Array(readFileSync(file)), {
  maxIssues: 200,
  externalResourceFunction: () => Promise.reject(new Error('no external resources')),
});
const i = report.issues;
console.log(JSON.stringify({
  validator: report.validatorVersion,
  errors: i.numErrors, warnings: i.numWarnings, infos: i.numInfos, hints: i.numHints,
  messages: i.messages.map(m => ({ severity: ['error', 'warning', 'info', 'hint'][m.severity],
    code: m.code, message: m.message, pointer: m.pointer })),
}));
