"""The clothsim process: started in the background, its per-frame stderr lines read on a thread so Blender's
UI never blocks, cancellable. No bpy here."""
import re
import subprocess
import threading

# clothsim writes one line per frame on stderr when it is not a terminal (tools/progress.cpp):
#   frame 0012  12/48  35.20 frames/s  ETA 1.0 s
PROGRESS_LINE = re.compile(r"^frame (\d+)\s+(\d+)/(\d+)")

EXIT_OK, EXIT_BAD_INPUT, EXIT_DIVERGED = 0, 2, 3


class ClothsimJob:
    def __init__(self, binary, scene_path, threads=0):
        self.command = [binary, "run", scene_path]
        if threads > 0:
            self.command += ["--threads", str(threads)]
        self.done_frames = 0
        self.total_frames = 0
        self.last_frame = None
        self.messages = []        # stderr lines that are not progress: clothsim's errors
        self.cancelled = False
        self._lock = threading.Lock()
        try:
            self._proc = subprocess.Popen(self.command, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                          stderr=subprocess.PIPE, text=True, bufsize=1)
        except OSError as e:
            raise RuntimeError(f"cannot start clothsim '{binary}': {e.strerror}; set its path in the add-on "
                               "preferences (Edit > Preferences > Add-ons > clothsim)") from e
        self._reader = threading.Thread(target=self._read_stderr, daemon=True)
        self._reader.start()

    def _read_stderr(self):
        for line in self._proc.stderr:
            line = line.rstrip("\n")
            m = PROGRESS_LINE.match(line)
            with self._lock:
                if m:
                    self.last_frame, self.done_frames, self.total_frames = (int(g) for g in m.groups())
                elif line.strip():
                    self.messages.append(line.strip())

    def progress(self):
        """(frames done, frames in all)."""
        with self._lock:
            return self.done_frames, self.total_frames

    def poll(self):
        """None while running, else the exit code (after stderr is fully read)."""
        code = self._proc.poll()
        if code is not None:
            self._reader.join()
        return code

    def wait(self):
        self._proc.wait()
        self._reader.join()
        return self._proc.returncode

    def cancel(self):
        self.cancelled = True
        if self._proc.poll() is None:
            self._proc.terminate()
            try:
                self._proc.wait(timeout=5)
            except subprocess.TimeoutExpired:
                self._proc.kill()
        self.wait()

    def error_text(self):
        """clothsim's own message for exit codes 2 and 3."""
        with self._lock:
            text = " ".join(self.messages)
        return text or f"clothsim exited with code {self._proc.returncode}"
