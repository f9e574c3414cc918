// Runs a Flamenco v3 job type's compileJob() outside the Manager and prints the tasks it authors as JSON.
//
// The Manager gives job compilers these globals (Flamenco's "Job Types" documentation): author.Task,
// author.Command, frameChunker, path, print, formatTimestampLocal. They are provided here as the Manager
// defines them, so the authored commands can be checked and then run for real.
//
// Usage: node flamenco_compile.js JOB_TYPE.js SETTINGS.json   (the tasks it authors, as JSON)
//        node flamenco_compile.js JOB_TYPE.js --settings      (the job type's settings)
"use strict";
const fs = require("fs");
const nodePath = require("path");
const vm = require("vm");

function frameChunker(frames, chunkSize) {
  const list = [];
  for (const part of `${frames}`.split(",")) {
    const [first, last] = part.trim().split("-").map(Number);
    for (let frame = first; frame <= (Number.isNaN(last) || last === undefined ? first : last); frame++) {
      list.push(frame);
    }
  }
  const chunks = [];
  for (let i = 0; i < list.length; i += chunkSize) {
    // each chunk as compact ranges, "1-4,8-9" where it has gaps
    const runs = [];
    for (const frame of list.slice(i, i + chunkSize)) {
      const run = runs[runs.length - 1];
      if (run && frame === run[1] + 1) run[1] = frame;
      else runs.push([frame, frame]);
    }
    chunks.push(runs.map(([a, b]) => (a === b ? `${a}` : `${a}-${b}`)).join(","));
  }
  return chunks;
}

function Task(name, type) {
  const task = { name, type, commands: [], dependencies: [] };
  task.addCommand = (command) => task.commands.push(command);
  task.addDependency = (other) => task.dependencies.push(other.name);
  return task;
}

const [jobTypeFile, settingsFile] = process.argv.slice(2);
if (settingsFile === "--settings") {
  // The job type's settings as the Manager hands them to the Blender add-on (their eval expressions).
  const definition = vm.createContext({});
  vm.runInContext(fs.readFileSync(jobTypeFile, "utf8") + "\nthis.JOB_TYPE = JOB_TYPE;", definition);
  console.log(JSON.stringify(definition.JOB_TYPE.settings));
  process.exit(0);
}
// SETTINGS.json is a job's settings, or a whole submission (POST /api/v3/jobs: name, type, settings), whose
// type must name this job type as the Manager does: the file's name, "_" as "-".
const given = JSON.parse(fs.readFileSync(settingsFile, "utf8"));
const typeName = nodePath.basename(jobTypeFile, ".js").replace(/_/g, "-");
if (given.settings !== undefined && given.type !== typeName) {
  console.error(`the job's type ${given.type} is not this job type, ${typeName}`);
  process.exit(3);
}
const job = { settings: given.settings || given, created: new Date(), tasks: [] };
job.addTask = (task) => job.tasks.push(task);
const context = {
  author: { Task, Command: (name, parameters) => ({ name, parameters }) },
  frameChunker,
  path: {
    join: nodePath.join,
    dirname: nodePath.dirname,
    basename: nodePath.basename,
    stem: (file) => nodePath.parse(file).name,
  },
  print: (...parts) => console.error(...parts),
  formatTimestampLocal: (date) => date.toISOString().slice(0, 19).replace(/[-:T]/g, ""),
};
vm.createContext(context);
vm.runInContext(fs.readFileSync(jobTypeFile, "utf8") + "\ncompileJob(job);", Object.assign(context, { job }));
console.log(JSON.stringify(job.tasks.map(({ name, type, commands, dependencies }) => ({ name, type, commands, dependencies }))));
