// Runs the Khronos glTF-Validator (npm package `gltf-validator`) on every file given and prints
// its findings: errors and warnings with their JSON pointers, and a count of infos and hints.
// Exits non-zero when any file has an error or cannot be validated.
//
// Usage: node scripts/validate_gltf.mjs FILE.glb|FILE.gltf...
// The validator is looked up in build/node (where `make check-gltf` installs it) unless
// GLTF_VALIDATOR names its module file.

import { readFile } from "node:fs/promises";
import path from "node:path";
import { fileURLToPath, pathToFileURL } from "node:url";

const here = path.dirname(fileURLToPath(import.meta.url));
const modulePath =
  process.env.GLTF_VALIDATOR ??
  path.join(here, "..", "build", "node", "node_modules", "gltf-validator", "module.mjs");
const validator = await import(pathToFileURL(modulePath).href);

const SEVERITY = ["error", "warning", "info", "hint"];

async function validate(file) {
  const bytes = new Uint8Array(await readFile(file));
  const report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 0,
    externalResourceFunction: async (uri) =>
      new Uint8Array(await readFile(path.resolve(path.dirname(file), decodeURIComponent(uri)))),
  });
  const issues = report.issues;
  console.log(
    `${file}: ${issues.numErrors} errors, ${issues.numWarnings} warnings, ` +
      `${issues.numInfos} infos, ${issues.numHints} hints (glTF-Validator ${report.validatorVersion})`,
  );
  const minor = new Map();
  for (const message of issues.messages) {
    if (message.severity <= 1) {
      console.log(`  ${SEVERITY[message.severity]} ${message.code} at ${message.pointer ?? "/"}: ${message.message}`);
    } else {
      const key = `${SEVERITY[message.severity]} ${message.code}`;
      minor.set(key, (minor.get(key) ?? 0) + 1);
    }
  }
  for (const [key, count] of [...minor].sort()) {
    console.log(`  ${key} × ${count}`);
  }
  return issues.numErrors;
}

const files = process.argv.slice(2);
if (files.length === 0) {
  console.error("usage: node scripts/validate_gltf.mjs FILE.glb...");
  process.exit(2);
}
let failed = 0;
for (const file of files) {
  try {
    if ((await validate(file)) > 0) {
      failed += 1;
    }
  } catch (error) {
    console.error(`${file}: cannot validate: ${error}`);
    failed += 1;
  }
}
process.exit(failed > 0 ? 1 : 0);
