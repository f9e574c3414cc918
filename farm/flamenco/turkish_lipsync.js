// SPDX-License-Identifier: GPL-3.0-or-later
//
// Flamenco v3 job type "Turkish Lip Sync": a scene built, rendered in frame chunks on any number of workers,
// then joined with its speech into one MP4 without re-encoding the video.
//
// Its tasks are the steps of farm/steps.toml (the STEPS block below is written from it, and the Open Job
// Description template of an episode is made from the same file): each task runs scripts/episode.py of a
// Turkish Lip Sync checkout with a Python that has PyAV, which starts Blender (the Manager's {blender}) for
// the Blender work. Two ways in:
// - from Blender's Flamenco add-on, the open .blend after Generate Animation: its chunks and the join (the
//   scene is built already);
// - an episode's scene, submitted as the JSON `scripts/episode.py job` writes (JOB/flamenco/<scene>.json):
//   its build first, from the episode's files.
//
// Install: copy this file into the "scripts" folder next to the Flamenco Manager executable and restart the
// Manager; see the manual's "Exports and farms" page (docs/user/exports-and-farms.md).

const JOB_TYPE = {
  label: "Turkish Lip Sync",
  description: "Build a lip-synced scene, render it in chunks, join them with the speech into one MP4",
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
      key: "checkout",
      type: "string",
      subtype: "dir_path",
      required: true,
      visible: "submission",
      description: "A Turkish Lip Sync checkout on the shared storage, as the workers see it",
    },
    {
      key: "python",
      type: "string",
      default: "python3",
      visible: "submission",
      description: "A Python with PyAV (python3 -m pip install av numpy) on the workers",
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
      visible: "submission",
      description: "Base folder of the output; the job name and a timestamp are added to it",
    },
    {
      key: "add_path_components",
      type: "int32",
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
    { key: "blendfile", type: "string", visible: "web", description: "The .blend to render" },

    // An episode's scene (written by scripts/episode.py job, never shown in Blender):
    { key: "scene", type: "string", visible: "web", description: "The episode's scene to build" },
    { key: "episode_folder", type: "string", visible: "web", description: "The episode's folder" },
    { key: "output_folder", type: "string", visible: "web", description: "The episode's output folder" },
  ],
};

// BEGIN STEPS: farm/steps.toml, written by `python -m tools.release.flamenco`; do not edit
const PROGRAM = [
  "{python}",
  "{checkout}/scripts/episode.py"
];
const STEPS = [
  {
    "name": "build",
    "arguments": [
      "--episode={episode}",
      "--scene={scene}",
      "--frames={frames}",
      "--blend={blend}",
      "--speech={speech}",
      "--blender={blender}"
    ],
    "after": null,
    "chunked": false,
    "blender": true,
    "episode_only": true
  },
  {
    "name": "render",
    "arguments": [
      "--blend={blend}",
      "--frames={chunk}",
      "--chunks={chunks}",
      "--engine={engine}",
      "--samples={samples}",
      "--blender={blender}"
    ],
    "after": "build",
    "chunked": true,
    "blender": true,
    "episode_only": false
  },
  {
    "name": "join",
    "arguments": [
      "--blend={blend}",
      "--frames={frames}",
      "--chunks={chunks}",
      "--engine={engine}",
      "--samples={samples}",
      "--speech={speech}",
      "--out={video}"
    ],
    "after": "render",
    "chunked": false,
    "blender": false,
    "episode_only": false
  }
];
const PATHS = {
  "blend": "{output}/{scene}/{scene}.blend",
  "speech": "{output}/{scene}/{scene}.wav",
  "chunks": "{output}/{scene}/chunks",
  "video": "{output}/{scene}.mp4"
};
// END STEPS

function compileJob(job) {
  print("Turkish Lip Sync job submitted");
  const settings = job.settings;
  if (!/^\s*\d+\s*-\s*\d+\s*$/.test(settings.frames)) {
    throw `Frames "${settings.frames}" must be one range START-END: the speech runs through them without gaps`;
  }
  const values = taskValues(job);
  const episode = Boolean(settings.scene);
  const tasksOfStep = {};
  for (const step of STEPS) {
    if (step.episode_only && !episode) {
      continue; // a .blend from Blender is built already
    }
    const chunks = step.chunked ? frameChunker(values.frames, settings.chunk_size) : [null];
    tasksOfStep[step.name] = chunks.map((chunk) => {
      const task = author.Task(chunk ? `${step.name}-${chunk}` : step.name, step.blender ? "blender" : "misc");
      const filled = Object.assign({}, values, chunk ? { chunk } : {});
      const program = PROGRAM.map((part) => fill(part, filled));
      const args = program.slice(1).concat([step.name], step.arguments.map((argument) => fill(argument, filled)));
      task.addCommand(author.Command("exec", { exe: program[0], args }));
      for (const before of tasksOfStep[step.after] || []) {
        task.addDependency(before); // every task of the step before
      }
      job.addTask(task);
      return task;
    });
  }
}

// The value of every {name} of the steps: the job's settings, and where the scene is and goes.
function taskValues(job) {
  const settings = job.settings;
  const values = {
    python: settings.python,
    checkout: settings.checkout,
    blender: "{blender}", // the Manager's variable: the worker's own Blender
    frames: settings.frames.replace(/\s/g, ""),
    engine: settings.engine,
    samples: `${settings.samples}`,
  };
  if (!settings.checkout) {
    throw "no checkout setting: the Turkish Lip Sync checkout the workers run scripts/episode.py from";
  }
  if (settings.scene) {
    Object.assign(values, {
      scene: settings.scene,
      episode: settings.episode_folder,
      output: settings.output_folder,
    });
    for (const name of Object.keys(PATHS)) {
      values[name] = fill(PATHS[name], values);
    }
    return values;
  }
  if (!settings.blendfile) {
    throw "no blendfile setting: submit the scene from Blender, or an episode's scene with its scene setting";
  }
  const video = renderOutputPath(job);
  settings.render_output_path = video; // so the job shows the output it really used
  return Object.assign(values, {
    blend: settings.blendfile,
    speech: settings.speech_wav || "",
    video,
    chunks: path.join(path.dirname(video), "chunks"),
  });
}

function fill(template, values) {
  return template.replace(/\{([a-z_]+)\}/g, (match, name) => {
    if (!(name in values)) {
      throw `the step argument ${template} needs ${name}, which this job does not have`;
    }
    return values[name];
  });
}

// Replace {timestamp} in the output path with the job's creation time.
function renderOutputPath(job) {
  const output = job.settings.render_output_path;
  if (!output) {
    throw "no render_output_path setting!";
  }
  return output.replace(/{([^}]+)}/g, (match, name) => (name == "timestamp" ? formatTimestampLocal(job.created) : match));
}
