// SPDX-License-Identifier: GPL-3.0-or-later
//
// Flamenco v3 job type "Turkish Lip Sync": renders a saved, lip-synced .blend in frame chunks on any number of
// workers, then joins the chunks with the speech into one MP4 without re-encoding the video.
//
// Install: copy this file into the "scripts" folder next to the Flamenco Manager executable and restart the
// Manager; the job type then appears in Blender's Flamenco add-on (Output Properties > Flamenco > Job Type).
// The workers need a checkout of the Turkish Lip Sync repository on the shared storage (its
// scripts/render.py renders each chunk inside the worker's Blender), and the worker that joins needs a Python
// with PyAV (`python3 -m pip install av`); see the manual's "Exports and farms" page
// (docs/user/exports-and-farms.md).

const JOB_TYPE = {
  label: "Turkish Lip Sync",
  description: "Render the lip-synced scene in chunks, then join them with the speech into one MP4",
  settings: [
    // Settings for artists to determine:
    {
      key: "frames",
      type: "string",
      required: true,
      eval: "f'{C.scene.frame_start}-{C.scene.frame_end}'",
      evalInfo: { showLinkButton: true, description: "Scene frame range" },
      description: "Frames to render, START-END: the speech plays from the scene's first frame",
    },
    {
      key: "chunk_size",
      type: "int32",
      default: 25,
      propargs: { min: 1, max: 10000 },
      visible: "submission",
      description: "Number of frames one worker renders in one task",
    },
    {
      key: "engine",
      type: "string",
      choices: ["CYCLES", "EEVEE", "WORKBENCH"],
      default: "CYCLES",
      visible: "submission",
      description: "Render engine of every chunk (EEVEE and Workbench need a GPU on each worker)",
    },
    {
      key: "samples",
      type: "int32",
      default: 16,
      propargs: { min: 1, max: 4096 },
      visible: "submission",
      description: "Render samples per pixel",
    },
    {
      key: "render_script",
      type: "string",
      subtype: "file_path",
      required: true,
      visible: "submission",
      description: "scripts/render.py of a Turkish Lip Sync checkout on the shared storage, as the workers see it",
    },
    {
      key: "join_python",
      type: "string",
      default: "python3",
      visible: "submission",
      description: "A Python with PyAV (python3 -m pip install av) on the worker that joins the chunks",
    },
    {
      key: "speech_wav",
      type: "string",
      subtype: "file_path",
      eval: "abspath(C.scene.get('turkish_lipsync_speech_wav', ''))",
      evalInfo: { showLinkButton: true, description: "The speech WAV of the last Generate Animation" },
      visible: "submission",
      description: "The speech audio to join under the video (empty: a silent video)",
    },

    // render_output_root + add_path_components determine the value of render_output_path.
    {
      key: "render_output_root",
      type: "string",
      subtype: "dir_path",
      required: true,
      visible: "submission",
      description: "Base folder of the output; the job name and a timestamp are added to it",
    },
    {
      key: "add_path_components",
      type: "int32",
      required: true,
      default: 0,
      propargs: { min: 0, max: 32 },
      visible: "submission",
      description: "Number of path components of the current blend file to use in the output path",
    },
    {
      key: "render_output_path",
      type: "string",
      subtype: "file_path",
      editable: false,
      eval:
        "str(Path(abspath(settings.render_output_root), last_n_dir_parts(settings.add_path_components), " +
        "jobname, '{timestamp}', jobname + '.mp4'))",
      description: "The joined video; the chunks go into a 'chunks' folder beside it",
    },

    // Automatically evaluated settings:
    { key: "blendfile", type: "string", required: true, visible: "web", description: "The .blend to render" },
  ],
};

function compileJob(job) {
  print("Turkish Lip Sync job submitted");
  const settings = job.settings;
  const output = renderOutputPath(job);
  settings.render_output_path = output; // so the job shows the output it really used
  const chunkFolder = path.join(path.dirname(output), "chunks");

  if (!/^\s*\d+\s*-\s*\d+\s*$/.test(settings.frames)) {
    throw `Frames "${settings.frames}" must be one range START-END: the speech runs through them without gaps`;
  }
  const renderTasks = [];
  const chunkFiles = [];
  for (const chunk of frameChunker(settings.frames.replace(/\s/g, ""), settings.chunk_size)) {
    const chunkFile = path.join(chunkFolder, `frames-${chunk}.mp4`);
    const task = author.Task(`render-${chunk}`, "blender");
    task.addCommand(
      author.Command("blender-render", {
        exe: "{blender}",
        exeArgs: "{blenderArgs}",
        argsBefore: [],
        blendfile: settings.blendfile,
        args: [
          "--python", settings.render_script, "--",
          "--frames", chunk,
          "--engine", settings.engine,
          "--samples", `${settings.samples}`,
          "--out", chunkFile,
        ],
      }),
    );
    renderTasks.push(task);
    chunkFiles.push(chunkFile);
  }

  const joinArgs = [settings.render_script, "--join", ...chunkFiles, "--out", output];
  if (settings.speech_wav) {
    joinArgs.push("--audio", settings.speech_wav);
  }
  const joinTask = author.Task("join", "misc");
  joinTask.addCommand(author.Command("exec", { exe: settings.join_python, args: joinArgs }));

  for (const task of renderTasks) {
    job.addTask(task);
    joinTask.addDependency(task); // the join waits for every chunk
  }
  job.addTask(joinTask);
}

// Replace {timestamp} in the output path with the job's creation time.
function renderOutputPath(job) {
  const output = job.settings.render_output_path;
  if (!output) {
    throw "no render_output_path setting!";
  }
  return output.replace(/{([^}]+)}/g, (match, name) => (name == "timestamp" ? formatTimestampLocal(job.created) : match));
}
