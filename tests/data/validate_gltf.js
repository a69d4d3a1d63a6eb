// Runs the Khronos glTF validator (npm gltf-validator) on one file: node validate_gltf.js NODE_PREFIX FILE.glb
// Prints {"errors": N, "warnings": N, "messages": [...]} as JSON.
const fs = require('fs');
const validator = require(process.argv[2] + '/node_modules/gltf-validator');
const data = new Uint8Array(fs.readFileSync(process.argv[3]));
validator.validateBytes(data).then((report) => {
  console.log(JSON.stringify({errors: report.issues.numErrors, warnings: report.issues.numWarnings,
    messages: report.issues.messages.slice(0, 12).map(m => `${m.severity} ${m.code} ${m.pointer || ''} ${m.message}`)}));
}).catch((e) => { console.log(JSON.stringify({crash: String(e)})); });
