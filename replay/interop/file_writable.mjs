// The IWritable the official TypeScript McapWriter writes through, over a node FileHandle.
// FileHandle.write may write fewer bytes than it is given (it makes one write(2)), so every
// buffer is written in a loop until all of it is in the file; a write that makes no
// progress is an error, not a loop. position() is the bytes written so far.
//   import { fileWritable } from "./file_writable.mjs";
//   const writable = fileWritable(await open(path, "w"));
export function fileWritable(file) {
  let position = 0n;
  return {
    write: async (buffer) => {
      for (let done = 0; done < buffer.byteLength; ) {
        const { bytesWritten } = await file.write(buffer, done, buffer.byteLength - done);
        if (bytesWritten <= 0) throw new Error(`write made no progress at byte ${position + BigInt(done)}`);
        done += bytesWritten;
      }
      position += BigInt(buffer.byteLength);
    },
    position: () => position,
  };
}
