#!/usr/bin/env node
// Runs the Khronos glTF validator on one .glb/.gltf file and prints a one-line JSON summary:
//   {"file": ..., "validator": ..., "errors": N, "warnings": N, "infos": N, "hints": N, "messages": [...]}
// Exits 0 when the asset has no errors, 1 when it has some, 2 when the validator cannot run.
// Usage: node validate-gltf.mjs FILE
import { readFile } from 'node:fs/promises';
import { basename } from 'node:path';

import validator from 'gltf-validator';

const kSeverity = ['error', 'warning', 'info', 'hint'];

const file = process.argv[2];
if (!file) {
  console.error('usage: node validate-gltf.mjs FILE.glb');
  process.exit(2);
}

try {
  const bytes = new Uint8Array(await readFile(file));
  const report = await validator.validateBytes(bytes, {
    uri: basename(file),
    maxIssues: 0,  // all of them: the test wants exact counts
    writeTimestamp: false,
  });
  const issues = report.issues;
  console.log(JSON.stringify({
    file,
    validator: report.validatorVersion,
    errors: issues.numErrors,
    warnings: issues.numWarnings,
    infos: issues.numInfos,
    hints: issues.numHints,
    // Only the first few: enough to say what is wrong without flooding the test log.
    messages: issues.messages.slice(0, 20).map((m) => `${kSeverity[m.severity] ?? m.severity} ${m.code} ${m.pointer ?? ''} ${m.message}`),
  }));
  process.exit(issues.numErrors > 0 ? 1 : 0);
} catch (error) {
  console.error(`validate-gltf: ${file}: ${error}`);
  process.exit(2);
}
